"""EcuNode on a virtual bus: stats, EcuStatus cadence, sim-time pacing, determinism, CLI."""

import signal
import subprocess
import sys
import threading
import time
import uuid

import can

from can_dbc import Receiver, encode
from can_transport import UnixSocketBus
from ecu import EcuConfig, EcuNode


def _wait_until(condition, what: str, timeout_s: float = 5.0) -> None:
    """Wait until ``condition()`` holds (checked every millisecond); fail naming ``what`` after ``timeout_s``."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert time.monotonic() < deadline, f"expected {what} within {timeout_s} s"
        time.sleep(0.001)


def _bus(channel):
    return can.Bus(interface="virtual", channel=channel)


def _inputs(k):
    """One cycle's inputs at the DBC's rates: wheels and pedals every 10 ms, the track every 50 ms."""
    c = k % 15
    frames = [encode("WheelSpeeds", {f"WheelSpeed{w}": 72.0 for w in ("FL", "FR", "RL", "RR")}, counter=c),
              encode("DriverInput", {"AccelPedal": 100.0, "BrakePedal": 0.0,
                                     "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}, counter=c)]
    if k % 5 == 0:
        frames.append(encode("ObjectTrack", {"ObjectValid": 1, "ObjectRange": 80.0 - k * 0.2,
                                             "ObjectRangeRate": -20.0, "ObjectLateral": 0.0}, counter=k // 5 % 15))
    return frames


def _drive_lockstep(cycles, extra=lambda k: []):
    channel = f"node-{uuid.uuid4().hex[:8]}"
    with _bus(channel) as ecu_bus, _bus(channel) as tester:
        node = EcuNode(ecu_bus, EcuConfig())
        out = []
        for k in range(cycles):
            for msg in _inputs(k) + extra(k):
                tester.send(msg)
            node.step(k * 0.01)
            while (m := tester.recv(timeout=0.0)) is not None:
                out.append((m.arbitration_id, bytes(m.data)))
        return node, out


def test_same_frames_same_outputs():
    assert _drive_lockstep(150)[1] == _drive_lockstep(150)[1]


def test_status_every_tenth_cycle_and_rejections_counted():
    bad = lambda k: [can.Message(arbitration_id=0x555, data=bytes(8), is_extended_id=False),
                     can.Message(arbitration_id=0xA0, data=bytes(8), is_extended_id=False)]
    node, out = _drive_lockstep(50, bad)
    ids = [i for i, _ in out]
    assert ids.count(0x090) == 50 and ids.count(0x3A0) == 5
    assert node.stats["UnknownFrame"] == 50 and node.stats["ChecksumError"] == 50
    assert node.stats["gate_interventions"] == 0 and node.cycles == 50


def test_sim_time_runs_one_cycle_per_sim_clock_frame():
    channel = f"sim-{uuid.uuid4().hex[:8]}"
    with _bus(channel) as ecu_bus, _bus(channel) as tester:
        node = EcuNode(ecu_bus, EcuConfig(sim_time=True))
        stop = threading.Event()
        result = {}
        thread = threading.Thread(target=lambda: result.setdefault("r", node.run(stop)))
        thread.start()
        rx = Receiver(names=["SafetyOverride", "EcuStatus"])
        modes = []
        for k in range(20):
            for msg in _inputs(k):
                tester.send(msg)
            tester.send(encode("SimClock", {"SimTimeMs": 1000 + 10 * k}, counter=k % 15))
            msg = tester.recv(timeout=2.0)
            while msg is not None and msg.arbitration_id != 0x090:
                msg = tester.recv(timeout=2.0)
            modes.append(rx.check(msg).signals["Mode"])
        good = node.stats["good"]
        for msg in _inputs(20):  # frames without a clock frame: taken in, and no cycle
            tester.send(msg)
        _wait_until(lambda: node.stats["good"] == good + len(_inputs(20)), "the node took in the last inputs")
        stop.set()
        thread.join(5.0)
        assert not thread.is_alive()
        late = [m.arbitration_id for m in iter(lambda: tester.recv(timeout=0.0), None)]
    assert 0x090 not in late
    assert result["r"].cycles == 20 and node.cycles == 20
    assert modes[:9] == [3] * 9 and modes[9:] == [0] * 11  # FAULT for the recovery cycles, then STANDBY


def test_cli_runs_and_exits_cleanly_on_sigterm(tmp_path):
    """``crd ecu`` on a shared bus: SIGTERM once it runs (its first SafetyOverride frame is the ready sign)."""
    channel = str(tmp_path / "can.sock")
    with UnixSocketBus(channel) as tester:  # the hub lives here, so the ECU joins it
        proc = subprocess.Popen([sys.executable, "-m", "cosim.cli.main", "ecu", "--interface", "crd_unix",
                                 "--channel", channel, "--strategy", "none"],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            first = tester.recv(timeout=60.0)  # the ECU sends every 10 ms once it runs
            while first is not None and first.arbitration_id != 0x090:
                first = tester.recv(timeout=60.0)
            assert first is not None, f"crd ecu sent no SafetyOverride within 60 s: {proc.poll()}"
            proc.send_signal(signal.SIGTERM)
            out, err = proc.communicate(timeout=10)
        finally:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    assert proc.returncode == 0, err
    ready, summary = out.strip().splitlines()  # issue 25: a ready line first, then the summary
    assert ready.startswith(f"ecu ready on crd_unix {channel}: strategy none")
    assert summary.startswith("ecu none: final mode FAULT; real-time:") and "cycles" in summary
