"""``python -m ecu`` and the spare ECU process (issue 10 item 4: the ECU's start-up).

A lock-step run starts a spare once its ECU has joined; the next run claims it
(its ECU is that process, with the run's own config and key) and gives the
same results as in process; a spare is never claimed from another working
directory, and never outlives the process that started it.
"""

from __future__ import annotations

import subprocess
import sys
import time

import pytest

from cosim.link.ecu_link import EcuOptions
from cosim.link.ecu_process import EcuProcess, discard_spare, prepare_spare, spare_pid
from cosim.loop.master import ClosedLoop, ecu_config, run_scenario
from cosim.scenarios.loader import scenario_from_dict
from tests.os_processes import process_gone

#: a short scenario in which the tightening ECU limits the throttle (object 25 m ahead)
SHORT = {"scenario": {"duration_s": 3.0}, "object": {"position_m": 25.0}}


def _gone_within(pid: int, timeout_s: float) -> bool:
    deadline = time.monotonic() + timeout_s
    while not process_gone(pid):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.02)
    return True


def test_the_next_run_claims_the_spare_and_gives_the_same_results(plant_fmu3):
    sc = scenario_from_dict(SHORT)
    reference = run_scenario(sc, plant_fmu3, "tightening")
    discard_spare()
    cold = ClosedLoop(sc, plant_fmu3, "tightening", ecu=EcuOptions(mode="process"))
    assert spare_pid() is None and cold.link.pid is not None
    first = cold.run()
    waiting = spare_pid()
    assert waiting is not None, "a lock-step run starts a spare once its ECU has joined"
    warm = ClosedLoop(sc, plant_fmu3, "tightening", ecu=EcuOptions(mode="process"))
    assert warm.link.pid == waiting, "the next run's ECU is the spare"
    second = warm.run()
    for rec in (first, second):
        a, b = reference.metrics.as_dict(), rec.metrics.as_dict()
        a.pop("wall_time_s"), b.pop("wall_time_s")
        assert a == b and rec.rows == reference.rows
        assert [e for e in rec.events if e.kind in ("ecu_lost", "bus_error", "auth_failure", "ecu_security_fault", "second_ecu")] == []
        assert "ecu tightening: final mode" in rec.ecu_report and "authentication failures 0" in rec.ecu_report
    assert process_gone(waiting) and process_gone(cold.link.pid)
    discard_spare()


def test_a_spare_is_not_claimed_from_another_directory(tmp_path, monkeypatch):
    discard_spare()
    prepare_spare()
    waiting = spare_pid()
    monkeypatch.chdir(tmp_path)  # a relative key or config path would now mean another file
    ecu = EcuProcess("crd_pair", str(tmp_path / "nobody.sock"), ecu_config(scenario_from_dict(SHORT)), True,
                     tmp_path)
    try:
        assert ecu.pid != waiting
        assert process_gone(waiting), "the spare that did not fit was stopped by its PID"
    finally:
        ecu.stop()
        discard_spare()


@pytest.mark.parametrize("exit_call", ["raise SystemExit(0)", "os._exit(0)"])
def test_an_unclaimed_spare_does_not_outlive_its_parent(exit_call):
    """At a normal exit ``atexit`` kills it; when the parent dies without one, the spare sees its stdin end."""
    code = ("import os\nfrom cosim.link import ecu_process\necu_process.prepare_spare()\n"
            f"print(ecu_process.spare_pid(), flush=True)\n{exit_call}\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True)
    assert _gone_within(int(out.stdout), 30.0)


def test_python_m_ecu_reports_an_error_in_one_line(tmp_path):
    missing = tmp_path / "missing.toml"
    out = subprocess.run([sys.executable, "-m", "ecu", "--interface", "virtual", "--channel", "x",
                          "--config", str(missing)], capture_output=True, text=True, timeout=60)
    assert out.returncode == 1 and out.stdout == ""
    assert out.stderr.startswith(f"error: {missing}: ") and len(out.stderr.splitlines()) == 1



def test_the_last_run_of_a_series_starts_no_spare(plant_fmu3, monkeypatch):
    """``crd run --ecu process`` (one run) starts no spare; in a series only the runs before the last do."""
    import cosim.link.bus_endpoint as endpoint
    from cosim.loop.experiment import run_strategies

    sc = scenario_from_dict(SHORT)
    discard_spare()
    started = []
    monkeypatch.setattr(endpoint, "prepare_spare", lambda: (started.append(True), prepare_spare()))
    try:
        run_strategies(sc, ["tightening"], None, ecu=EcuOptions(mode="process"))
        assert started == [] and spare_pid() is None
        records = run_strategies(sc, ["none", "tightening"], None, ecu=EcuOptions(mode="process"))
        assert started == [True] and spare_pid() is None  # the first run's spare became the second's ECU
        assert [r.error for r in records] == [None, None]
    finally:
        discard_spare()
