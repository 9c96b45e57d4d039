"""Finding 8 of issue 15: a lock-step stall of the ECU, loss of the ECU, and honest exits.

Before: SIGSTOP on the ECU process for 2 s gave ``ecu_lost`` (1 s reply timeout), the ECU was
never re-admitted, a false ``second_ecu`` followed, the car collided and ``crd run`` exited 0;
after the ECU died every frame logged a ``bus_error`` event.

Now: the master waits for a stalled ECU with simulated time held, so a 2 s stop leaves the run
identical to an unstalled one; past ``--stall-timeout`` the run stops with an error (exit 1);
an ECU that dies is ``ecu_lost`` and the run exits 4 unless ``[checks] expect_events`` lists
it; the ``bus_error`` flood is rate-limited and summarised.

Every ECU process is signalled and stopped by its PID; ``finally`` blocks continue a stopped one.
"""

from __future__ import annotations

import json
import logging
import os
import signal
import threading
import time

import pytest

from cosim.cli.main import main
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import ClosedLoop, run_scenario
from cosim.results.events import KEEP_FIRST, SUPPRESSED
from cosim.scenarios.loader import scenario_from_dict
from tests.os_processes import process_gone

#: the tightening ECU limits the throttle (object 25 m ahead): a lost ECU changes the result
SHORT = {"scenario": {"duration_s": 3.0}, "object": {"position_m": 25.0}}


def _comparable(record) -> dict:
    m = record.metrics.as_dict()
    m.pop("wall_time_s")
    return m


@pytest.mark.wallclock
def test_sigstop_for_2_s_is_waited_out_and_the_run_is_unchanged(plant_fmu3):
    """Wall-clock by nature: the ECU is stopped for 2 s of wall time (SIGSTOP, a timer sends SIGCONT), longer
    than the 1 s reply timeout, and the run must wait it out."""
    sc = scenario_from_dict(SHORT)
    reference = run_scenario(sc, plant_fmu3, "tightening")
    loop = ClosedLoop(sc, plant_fmu3, "tightening", ecu=EcuOptions(mode="process"))
    pid = loop.link.pid
    stopped: list[float] = []
    resume = threading.Timer(2.0, lambda: os.kill(pid, signal.SIGCONT))

    def stop_at_1s(t_s: float, _duration_s: float) -> None:
        if t_s >= 1.0 and not stopped:
            os.kill(pid, signal.SIGSTOP)
            stopped.append(time.monotonic())
            resume.start()

    try:
        record = loop.run(progress=stop_at_1s)
    finally:
        resume.cancel()
        if not process_gone(pid):
            os.kill(pid, signal.SIGCONT)
    assert stopped and record.error is None and record.status == "ok"
    assert _comparable(record) == _comparable(reference) and record.rows == reference.rows
    kinds = [e.kind for e in record.events]
    assert "ecu_lost" not in kinds and "second_ecu" not in kinds
    stall = [e for e in record.events if e.kind == "ecu_stall"]
    assert len(stall) == 1 and stall[0].t_s == pytest.approx(1.0, abs=0.011)
    assert process_gone(pid)


@pytest.mark.wallclock
def test_a_stall_past_the_limit_stops_the_run_loudly(plant_fmu3):
    """Wall-clock by nature: the stall limit (1 s) is wall time, and the run must stop once it has passed."""
    sc = scenario_from_dict(SHORT)
    loop = ClosedLoop(sc, plant_fmu3, "tightening", ecu=EcuOptions(mode="process", stall_timeout_s=1.0))
    pid = loop.link.pid

    def stop_at_1s(t_s: float, _duration_s: float) -> None:
        if t_s >= 1.0:
            os.kill(pid, signal.SIGSTOP)

    try:
        started = time.monotonic()
        record = loop.run(progress=stop_at_1s)
        wall_s = time.monotonic() - started
    finally:
        if not process_gone(pid):
            os.kill(pid, signal.SIGCONT)
    assert record.status == "error" and "ECU stalled" in record.error and "t = 1.0" in record.error
    assert "--stall-timeout 1 s" in record.error
    assert record.metrics.sim_time_s == pytest.approx(1.0, abs=0.011)  # simulated time never went on
    assert record.rows[-1][0] == pytest.approx(1.0, abs=0.011)  # results up to the stall kept
    assert [e.kind for e in record.events if e.kind in ("ecu_stalled", "ecu_lost")] == ["ecu_stalled"]
    assert wall_s < 1.0 + 20.0  # the limit, plus start-up, the 1 s of driving and stopping the child
    assert process_gone(pid)  # stopped by PID although it was SIGSTOPped


def _scenario_file(tmp_path, expect: str = "") -> str:
    path = tmp_path / "s.toml"
    path.write_text(f"[scenario]\nduration_s = 20.0\n[object]\nposition_m = 25.0\n[checks]\n{expect}")
    return str(path)


def _waiting_spare(pid: str) -> bool:
    """A spare ECU not yet claimed by a run (cosim.link.ecu_process) still writes to /dev/null."""
    try:
        return os.readlink(f"/proc/{pid}/fd/1") == "/dev/null"
    except OSError:
        return True


def _kill_the_ecu_at(out_dir, t_s: float) -> threading.Thread:
    """Kill (by PID) this process's ``crd ecu`` child once the streamed time series reaches ``t_s``."""

    def ecu_child() -> int | None:
        for entry in os.listdir("/proc"):
            if entry.isdigit():
                try:
                    with open(f"/proc/{entry}/stat") as f:
                        ppid = int(f.read().split(")")[-1].split()[1])
                    with open(f"/proc/{entry}/cmdline", "rb") as f:
                        argv = f.read().split(b"\0")
                except (FileNotFoundError, ProcessLookupError, IndexError):
                    continue
                if ppid == os.getpid() and argv[1:3] == [b"-m", b"ecu"] and not _waiting_spare(entry):
                    return int(entry)
        return None

    def reached() -> bool:
        try:
            lines = (out_dir / "tightening" / "timeseries.csv").read_text().splitlines()
            return len(lines) > 1 and float(lines[-1].split(",")[0]) >= t_s
        except (FileNotFoundError, ValueError):
            return False

    def kill() -> None:
        deadline = time.monotonic() + 60.0
        while time.monotonic() < deadline:
            pid = ecu_child()
            if pid is not None and reached():
                os.kill(pid, signal.SIGKILL)
                return
            time.sleep(0.02)

    thread = threading.Thread(target=kill, daemon=True)
    thread.start()
    return thread


@pytest.mark.wallclock
def test_a_lost_ecu_exits_4_with_a_quiet_event_log(plant_fmu3, tmp_path, capsys, caplog):
    """Wall-clock: the ECU is killed once 2 s are on disk (a condition), and the loss is seen after the reply
    timeout (wall time); where the run stands by then is a race, so the checks are ranges."""
    out = tmp_path / "out"
    killer = _kill_the_ecu_at(out, 2.0)
    with caplog.at_level(logging.WARNING, logger="cosim.link"):
        code = main(["run", _scenario_file(tmp_path), "--out", str(out), "--ecu", "process"])
    killer.join()
    printed = capsys.readouterr().out
    assert code == 4, printed
    assert "FAULT: tightening: t=" in printed and "ecu_lost" in printed
    events = json.loads((out / "tightening" / "events.json").read_text())["events"]
    errors = [e for e in events if e["kind"] == "bus_error"]
    counts = json.loads((out / "metrics.json").read_text())["runs"][0]["event_counts"]
    assert counts["ecu_lost"] == 1
    # a dead peer fails every frame: counted in full, recorded and logged only the first few times
    assert counts.get("bus_error", 0) > 2 * KEEP_FIRST
    assert len(errors) <= KEEP_FIRST + 2
    assert [e for e in events if e["kind"] == SUPPRESSED and e["detail"].startswith("bus_error:")]
    assert sum("bus error" in r.getMessage() for r in caplog.records) <= KEEP_FIRST + 2


@pytest.mark.wallclock
def test_an_expected_lost_ecu_exits_0(plant_fmu3, tmp_path, capsys):
    """Wall-clock, as the test above: the loss is seen after the reply timeout (wall time)."""
    out = tmp_path / "out"
    killer = _kill_the_ecu_at(out, 2.0)
    code = main(["run", _scenario_file(tmp_path, 'expect_events = ["ecu_lost"]'), "--out", str(out),
                 "--ecu", "process"])
    killer.join()
    assert code == 0, capsys.readouterr().out
    assert json.loads((out / "metrics.json").read_text())["runs"][0]["event_counts"]["ecu_lost"] == 1


def test_an_expected_event_that_does_not_occur_fails_the_check(plant_fmu3, tmp_path, capsys):
    code = main(["run", _scenario_file(tmp_path, 'expect_events = ["ecu_lost"]'), "--out", str(tmp_path / "o")])
    assert code == 3
    assert "CHECK FAILED: expect_events: expected ecu_lost, which did not occur" in capsys.readouterr().out
