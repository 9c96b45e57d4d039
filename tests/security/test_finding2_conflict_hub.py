"""Issue 25, finding 2: a detected second sender must not disarm collision avoidance.

Reproduction on a ``crd_unix`` hub without a key: ``crd ecu --sim-time`` as its own
process, the co-simulation attached to it in lock-step, and a forger, a third
participant, that sends a pass-through ``SafetyOverride`` (the next counter, a
valid CRC) right after every third genuine one. Before issue 25 the gateway
detected it (``second_ecu``, exit 4) and then ignored every override: the
driver's full throttle alone, and the car hit the cyclist at 33.8 m/s. Now it
applies the most restrictive valid override (``cosim/world/gateway.py``), so the
genuine ECU's limits and braking stay in force; the run still reports the
conflict and exits non-zero.
"""

from __future__ import annotations

import shutil
import tempfile
import threading
import time
from pathlib import Path

import can
import pytest

from can_dbc import LAYOUTS, encode
from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.link.ecu_process import EcuProcess
from cosim.loop.master import ClosedLoop, ecu_config, run_scenario
from cosim.results.events import unexpected_faults
from cosim.scenarios.loader import load_scenario
from tests.os_processes import process_gone

OVERRIDE_ID = LAYOUTS["SafetyOverride"].frame_id
PASS = {"Mode": 0, "OverrideActive": 0, "ThrottleLimit": 100.0, "BrakeDecelRequest": 0.0}


class Forger(threading.Thread):
    """A third participant on the hub: after every ``every``-th genuine SafetyOverride, a pass-through one."""

    def __init__(self, channel: str, every: int = 3) -> None:
        super().__init__(daemon=True)
        self.bus = can.Bus(interface="crd_unix", channel=channel)
        self.every, self.sent, self.seen = every, 0, 0
        self.stop = threading.Event()

    def run(self) -> None:
        while not self.stop.is_set():
            try:
                msg = self.bus.recv(0.05)
            except can.CanOperationError:  # the hub's host (the co-simulation) left: the run is over
                return
            if msg is None or msg.arbitration_id != OVERRIDE_ID:
                continue
            self.seen += 1
            if self.seen % self.every == 0:
                self.bus.send(encode("SafetyOverride", PASS, ((msg.data[1] & 0x0F) + 1) % 15))
                self.sent += 1

    def close(self) -> None:
        self.stop.set()
        self.join(5.0)
        self.bus.shutdown()


@pytest.fixture
def sock_dir():
    path = Path(tempfile.mkdtemp(prefix="crd-t-"))  # short: a socket path is at most 107 bytes
    yield path
    shutil.rmtree(path, ignore_errors=True)


@pytest.mark.wallclock  # three processes' threads on a hub; lock-step keeps the result independent of timing
def test_a_forger_on_the_hub_is_reported_and_does_not_disarm_the_ecu(plant_fmu3, sock_dir):
    sc = load_scenario(PAPER_SCENARIO)
    reference = run_scenario(sc, plant_fmu3, "tightening")  # the working ECU alone, in process
    channel = str(sock_dir / "can.sock")
    ecu = EcuProcess("crd_unix", channel, ecu_config(sc, "tightening"), True, sock_dir)
    forger = None
    try:
        loop = ClosedLoop(sc, plant_fmu3, "tightening", ecu=EcuOptions(mode="attach", channel=channel))
        deadline = time.monotonic() + 15.0
        while loop.link.bus.peer_count < 1:  # the ECU joined: the forger joins after it
            assert time.monotonic() < deadline, "the ECU process did not join"
            time.sleep(0.01)
        forger = Forger(channel)
        forger.start()
        while loop.link.bus.peer_count < 2:
            assert time.monotonic() < deadline, "the forger did not join"
            time.sleep(0.01)
        rec = loop.run()
    finally:
        if forger is not None:
            forger.close()
        ecu.stop()
    assert process_gone(ecu.pid)
    assert forger.sent >= 100, f"the forger sent only {forger.sent} frames"
    assert rec.error is None
    assert not rec.metrics.collided, f"collided at {rec.metrics.impact_speed_mps:.1f} m/s"
    kinds = {e.kind for e in rec.events}
    assert "second_ecu" in kinds  # reported ...
    assert "ecu_security_fault" in kinds  # ... by the gateway, and by the ECU, which saw a foreign override
    assert unexpected_faults([rec])  # so crd run exits 4
    # the genuine ECU stayed in control: never less braking than it asked for, never more speed
    assert rec.metrics.max_speed_mps <= reference.metrics.max_speed_mps + 1e-9
    assert rec.metrics.final_gap_m >= reference.metrics.final_gap_m - 0.5
