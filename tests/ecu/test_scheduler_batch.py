"""The sim-time scheduler on a batching bus (``crd_pair``): a cycle's frames leave in one write."""

from __future__ import annotations

import threading

from can_dbc import Receiver, encode
from can_transport import PairSocketBus
from ecu import EcuConfig, EcuNode
from tests.ecu.test_node import _inputs


def test_each_sim_time_cycle_sends_its_frames_in_one_write(tmp_path, monkeypatch) -> None:
    channel = str(tmp_path / "c.sock")
    with PairSocketBus(channel) as tester, PairSocketBus(channel, role="connect") as ecu_bus:
        assert tester.wait_for_peer(5.0)
        writes: list[int] = []
        real = ecu_bus._send_records
        monkeypatch.setattr(ecu_bus, "_send_records", lambda records, timeout: (writes.append(len(records)),
                                                                                real(records, timeout)))
        node = EcuNode(ecu_bus, EcuConfig(sim_time=True))
        stop = threading.Event()
        thread = threading.Thread(target=node.run, args=(stop,))
        thread.start()
        try:
            rx, ids = Receiver(names=["SafetyOverride", "SteeringOverride", "EcuStatus", "EcuRegionStatus"]), []
            for k in range(20):
                for msg in [*_inputs(k), encode("SimClock", {"SimTimeMs": 10 * k}, counter=k % 15)]:
                    tester.send(msg)
                while len(ids) < 2 * (k + 1) + 2 * (k // 10 + 1):  # this cycle's two requests (and the statuses)
                    msg = tester.recv(timeout=5.0)
                    ids.append(rx.check(msg).name)
        finally:
            stop.set()
            thread.join(5.0)
    assert node.cycles == 20 and ids.count("SafetyOverride") == ids.count("SteeringOverride") == 20
    assert ids.count("EcuStatus") == ids.count("EcuRegionStatus") == 2
    # one write a cycle of 24-byte records: SafetyOverride and SteeringOverride, EcuRegionStatus and EcuStatus
    # every 10th cycle
    assert writes == [96] + [48] * 9 + [96] + [48] * 9
