"""The sim-time scheduler on a batching bus (``crd_pair``): a cycle's frames leave in one write."""

from __future__ import annotations

import threading

import pytest

from can_dbc import Receiver, encode
from can_transport import PairSocketBus
from ecu import EcuConfig, EcuNode
from tests.ecu.test_node import _inputs


@pytest.mark.parametrize("equipment, requests, statuses", [
    ("longitudinal", ["SafetyOverride"], ["EcuStatus"]),
    ("planar_steering", ["SafetyOverride", "SteeringOverride"], ["EcuRegionStatus", "EcuStatus"])])
def test_each_sim_time_cycle_sends_its_frames_in_one_write(tmp_path, monkeypatch, equipment, requests,
                                                           statuses) -> None:
    channel = str(tmp_path / "c.sock")
    with PairSocketBus(channel) as tester, PairSocketBus(channel, role="connect") as ecu_bus:
        assert tester.wait_for_peer(5.0)
        writes: list[int] = []
        real = ecu_bus._send_records
        monkeypatch.setattr(ecu_bus, "_send_records", lambda records, timeout: (writes.append(len(records)),
                                                                                real(records, timeout)))
        node = EcuNode(ecu_bus, EcuConfig(sim_time=True, equipment=equipment))
        stop = threading.Event()
        thread = threading.Thread(target=node.run, args=(stop,))
        thread.start()
        try:
            rx, ids = Receiver(names=["SafetyOverride", "SteeringOverride", "EcuStatus", "EcuRegionStatus"]), []
            for k in range(20):
                for msg in [*_inputs(k), encode("SimClock", {"SimTimeMs": 10 * k}, counter=k % 15)]:
                    tester.send(msg)
                while len(ids) < len(requests) * (k + 1) + len(statuses) * (k // 10 + 1):  # requests, statuses
                    msg = tester.recv(timeout=5.0)
                    ids.append(rx.check(msg).name)
        finally:
            stop.set()
            thread.join(5.0)
    assert node.cycles == 20 and all(ids.count(name) == 20 for name in requests)
    assert all(ids.count(name) == 2 for name in statuses) and set(ids) == {*requests, *statuses}
    # one write a cycle of 24-byte records: the equipment's requests, its statuses every 10th cycle
    per_cycle, statuses_b = 24 * len(requests), 24 * len(statuses)
    assert writes == [per_cycle + statuses_b] + [per_cycle] * 9 + [per_cycle + statuses_b] + [per_cycle] * 9
