"""Finding 7 of issue 15: results only at the end.

* Ctrl-C (or SIGTERM) after some simulated seconds wrote nothing; now the time series and the
  CAN log are on disk while the run goes, and the signal ends the run with its results so far,
  ``metrics.json`` saying ``interrupted``, and exit 130 / 143.
* ``--out`` under a regular file failed only after the whole run; now it fails before it starts.

The signal tests start ``crd run`` as a subprocess, wait (a condition, not a sleep) until the
streamed time series shows 3 simulated seconds, signal it by PID and wait for it to end.
"""

from __future__ import annotations

import json
import signal

import can
import pytest

from cosim.cli.main import main
from tests.os_processes import crd_signalled_when, last_time_s

LONG = """
[scenario]
name = "long"
duration_s = 3600.0
[ecu]
strategy = "tightening"
"""


@pytest.mark.wallclock
@pytest.mark.parametrize("sig, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_signal_mid_run_keeps_the_results_so_far(plant_fmu3, tmp_path, sig, code):
    """Wall-clock: the signal lands wherever the run is once 3 s are on disk, so the check is a range."""
    scenario = tmp_path / "long.toml"
    scenario.write_text(LONG)
    out = tmp_path / "out"
    series = out / "tightening" / "timeseries.csv"
    def still_running() -> None:
        running = json.loads((out / "metrics.json").read_text())
        assert running["status"] == "running" and running["runs"] == []

    returncode, err = crd_signalled_when(["run", str(scenario), "--out", str(out)],
                                         lambda: last_time_s(series) >= 3.0, "3 s of simulated time on disk",
                                         sig, check=still_running)
    assert returncode == code, err
    assert f"interrupted: tightening interrupted by {sig.name}" in err
    metrics = json.loads((out / "metrics.json").read_text())
    run = metrics["runs"][0]
    assert metrics["status"] == "interrupted" and run["status"] == "interrupted"
    assert run["interrupted_by"] == sig.name and 3.0 <= run["sim_time_s"] < 3600.0
    t_last = last_time_s(series)
    assert run["sim_time_s"] - 0.011 <= t_last <= run["sim_time_s"]  # every cycle up to the stop
    frames = list(can.BLFReader(str(out / "tightening" / "can.blf")))
    # the log is complete up to the stop and closed (stamps: the scenario's start time + simulated time)
    assert frames and frames[-1].timestamp - frames[0].timestamp == pytest.approx(t_last, abs=1e-6)
    events = json.loads((out / "tightening" / "events.json").read_text())["events"]
    assert [e["kind"] for e in events][-1] == "interrupted"
    assert (out / "speed_profiles.png").exists()


def test_out_under_a_regular_file_fails_before_the_run(tmp_path, capsys):
    scenario = tmp_path / "s.toml"
    scenario.write_text(LONG)
    blocker = tmp_path / "results"
    blocker.write_text("not a directory")
    assert main(["run", str(scenario), "--out", str(blocker / "run1")]) == 1
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1] == (f"error: --out {blocker / 'run1'}: cannot write results under "
                                            f"{blocker}: it is a file, not a directory")
    assert " s sim" not in err  # no progress line: nothing ran
    assert blocker.read_text() == "not a directory"


def test_a_strategy_directory_that_is_a_file_fails_before_the_run(tmp_path, capsys):
    scenario = tmp_path / "s.toml"
    scenario.write_text(LONG)
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "tightening").write_text("")
    assert main(["run", str(scenario), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert "tightening: it is a file, not a directory" in err and " s sim" not in err
