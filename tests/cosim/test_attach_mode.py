"""Issue 25, finding 4: attach mode that tells the truth.

Before: a scenario with ``[ecu] peak_decel_mps2 = 6.5`` ran the attached ECU's defaults and its
report still said 6.5; ``crd ecu --config scenario.toml`` was refused; a second run on one
``crd ecu`` stalled. Now ``crd ecu`` reads a scenario's ``[ecu]``, prints a ready line and
serves run after run, each from a clean state (identical to the run in process); it announces
what it runs (``EcuIdentity``), a run whose scenario says otherwise stops with one line, and
``--ecu-settings ecu`` runs with the ECU's settings and records them.

Each ECU process is started by the test and stopped by its PID in a ``finally``.
"""

from __future__ import annotations

import json
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from cosim.cli.main import main as crd
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import ClosedLoop, run_scenario
from cosim.scenarios.loader import load_scenario
from ecu import EcuConfig
from tests.os_processes import process_gone

SCENARIO = """
[scenario]
name = "finding4"
duration_s = 3.0
[object]
position_m = 25.0
[ecu]
strategy = "tightening"
peak_decel_mps2 = 6.5
"""


@pytest.fixture
def bench():
    """A private directory (a socket path is at most 107 bytes) with the scenario file."""
    path = Path(tempfile.mkdtemp(prefix="crd-a-"))
    (path / "s.toml").write_text(SCENARIO)
    yield path
    shutil.rmtree(path, ignore_errors=True)


class Ecu:
    """``python -m ecu ARGS`` on ``crd_unix`` in ``bench``; ``ready``: wait (bounded) for its ready line."""

    def __init__(self, bench: Path, *args: str, ready: bool = True) -> None:
        self.channel = str(bench / "can.sock")
        self.proc = subprocess.Popen([sys.executable, "-m", "ecu", "--interface", "crd_unix", "--channel",
                                      self.channel, "--sim-time", *args],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.ready = self._line(lambda line: line.startswith("ecu ready"), 30.0) if ready else self._hub(30.0)

    def _hub(self, timeout_s: float) -> None:
        """Wait until the ECU hosts the hub (its socket exists): it outlives each run's master."""
        deadline = time.monotonic() + timeout_s
        while not Path(self.channel).exists():
            assert self.proc.poll() is None and time.monotonic() < deadline, f"no hub: {self.stop()}"
            time.sleep(0.02)

    def _line(self, wanted, timeout_s: float) -> str:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if select.select([self.proc.stdout], [], [], max(0.0, deadline - time.monotonic()))[0]:
                line = self.proc.stdout.readline()
                if not line:
                    break
                if wanted(line):
                    return line.strip()
        raise AssertionError(f"crd ecu printed no such line within {timeout_s} s: {self.stop()}")

    def stop(self) -> str:
        """SIGTERM by PID, wait, and everything it printed."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            out, err = self.proc.communicate(timeout=10.0)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            out, err = self.proc.communicate()
        return out + err


def _attach(bench: Path, ecu: Ecu, **options) -> ClosedLoop:
    return ClosedLoop(load_scenario(bench / "s.toml"), _fmu(), "tightening",
                      ecu=EcuOptions(mode="attach", channel=ecu.channel, **options))


def _fmu():
    from fmu_plant.build import ensure_fmu
    return ensure_fmu(fmi_version=3)


def _same_run(a, b) -> None:
    ma, mb = a.metrics.as_dict(), b.metrics.as_dict()
    ma.pop("wall_time_s"), mb.pop("wall_time_s")
    assert ma == mb and a.rows == b.rows


@pytest.mark.wallclock  # an ECU process; its ready line is a condition wait
def test_crd_ecu_reads_a_scenario_files_ecu_table_and_says_when_it_is_ready(bench):
    ecu = Ecu(bench, "--config", str(bench / "s.toml"))  # before: unknown top-level keys [...]; expected only [ecu]
    try:
        from ecu.config_digest import announced_digest

        assert ecu.ready.startswith(f"ecu ready on crd_unix {ecu.channel}: strategy tightening")
        assert f"config digest 0x{announced_digest(EcuConfig(peak_decel_mps2=6.5)):08x}" in ecu.ready
    finally:
        ecu.stop()
    assert process_gone(ecu.proc.pid)


@pytest.mark.wallclock  # processes on a hub; lock-step keeps the results independent of timing
def test_two_runs_on_one_ecu_each_from_a_clean_state_as_in_process(bench):
    reference = run_scenario(load_scenario(bench / "s.toml"), _fmu(), "tightening")  # the ECU in process
    ecu_file = bench / "ecu.toml"  # the scenario's [ecu] as an ECU settings file
    ecu_file.write_text('[ecu]\nstrategy = "tightening"\npeak_decel_mps2 = 6.5\n')
    ecu = Ecu(bench, "--config", str(ecu_file), ready=False)  # (a ready line is new: wait for its hub)
    try:
        first = _attach(bench, ecu).run()
        second = _attach(bench, ecu).run()  # before: "ECU stalled: no SafetyOverride for t = 0.000 s"
    finally:
        printed = ecu.stop()
    assert process_gone(ecu.proc.pid)
    assert [first.error, second.error] == [None, None]
    for record in (first, second):
        _same_run(record, reference)  # the scenario's 6.5 m/s2 each time, each from a clean state
        assert record.ecu_settings["known_as"] == "the scenario's [ecu]"  # the report records them
        assert record.ecu_settings["settings"]["peak_decel_mps2"] == 6.5
    summaries = [line for line in printed.splitlines() if line.startswith("ecu tightening: final mode")]
    assert [line.rsplit("; ", 1)[-1] for line in summaries] == ["run 1", "run 2"]


@pytest.mark.wallclock
def test_a_scenario_the_ecu_does_not_run_is_a_one_line_error_or_runs_with_the_ecus_settings(bench, capsys):
    from ecu.config_digest import announced_digest

    in_process = run_scenario(load_scenario(bench / "s.toml"), _fmu(), "tightening")  # with the scenario's 6.5
    ecu = Ecu(bench, ready=False)  # crd ecu with its defaults: peak_decel_mps2 9.0
    try:
        out = bench / "out"
        args = ["run", str(bench / "s.toml"), "--ecu", "attach", "--bus-channel", ecu.channel, "--out"]
        assert crd(args + [str(out / "refused")]) == 1  # before: 0, the ECU's defaults run and recorded as 6.5
        err = capsys.readouterr().err.strip().splitlines()
        assert err[-1].startswith("error: the ECU on crd_unix") and "runs other settings than the scenario's [ecu]" \
            in err[-1] and f"0x{announced_digest(EcuConfig()):08x}" in err[-1] and "--ecu-settings ecu" in err[-1]
        assert (out / "refused" / "tightening" / "timeseries.csv").read_text().count("\n") == 1  # a header: no cycle
        assert crd(args + [str(out / "ecu"), "--ecu-settings", "ecu"]) == 0  # before: no such option
    finally:
        ecu.stop()
    run = json.loads((out / "ecu" / "metrics.json").read_text())["runs"][0]
    settings = run["ecu_settings"]
    assert settings["source"] == "ecu" and settings["known_as"] == "crd ecu's defaults for strategy tightening"
    assert settings["settings"]["peak_decel_mps2"] == 9.0  # what the ECU really used ...
    resolved = (out / "ecu" / "config.resolved.toml").read_text()
    assert "peak_decel_mps2 = 9.0" in resolved and "peak_decel_mps2 = 6.5" not in resolved  # ... not the scenario's
    assert "## ECU settings" in (out / "ecu" / "report.md").read_text()
    assert run["max_speed_mps"] != pytest.approx(in_process.metrics.max_speed_mps, abs=1e-6)  # 9.0 acts otherwise


@pytest.mark.wallclock
def test_the_ecus_settings_file_is_checked_against_its_announcement(bench, capsys):
    ecu_file = bench / "ecu.toml"
    ecu_file.write_text("[ecu]\nstrategy = \"tightening\"\nstandoff_m = 2.5\n")
    ecu = Ecu(bench, "--config", str(ecu_file), ready=False)
    try:
        named = _attach(bench, ecu, ecu_settings=str(ecu_file)).run()
        wrong = bench / "wrong.toml"
        wrong.write_text("[ecu]\nstandoff_m = 3.0\n")
        assert crd(["run", str(bench / "s.toml"), "--ecu", "attach", "--bus-channel", ecu.channel,
                    "--ecu-settings", str(wrong), "--out", str(bench / "o")]) == 1
    finally:
        ecu.stop()
    assert named.ecu_settings["known_as"] == f"the settings file {ecu_file}"
    assert named.ecu_settings["settings"]["standoff_m"] == 2.5
    assert capsys.readouterr().err.strip().splitlines()[-1].startswith(f"error: --ecu-settings {wrong}: its settings")


def test_ecu_settings_other_than_the_scenarios_need_an_ecu_on_a_bus():
    from cosim.link.ecu_link import EcuLinkError

    with pytest.raises(EcuLinkError, match="--ecu-settings ecu: expected --ecu attach or process"):
        EcuOptions(ecu_settings="ecu")


@pytest.mark.wallclock  # processes on a hub; lock-step keeps the results independent of timing
def test_a_planar_scene_runs_on_an_ecu_equipped_for_it(bench, capsys):
    """A planar scene equips the ECU with the planar sensors and steering (``Scenario.equipment``): an ECU that
    read the scenario's ``[ecu]`` without it (which leaves the scene out) is refused, naming the equipment; one
    whose ``[ecu]`` states it runs as in process, the planar frames on the bus."""
    from can_dbc import LAYOUTS_BY_ID
    from can_dbc.planar import TRACK_SLOTS

    planar = SCENARIO + '[driver.steering]\nmodel = "held"\n'  # a steering driver: a scene of the plane
    (bench / "p.toml").write_text(planar)
    ecu = Ecu(bench, "--config", str(bench / "p.toml"))
    try:
        assert crd(["run", str(bench / "p.toml"), "--ecu", "attach", "--bus-channel", ecu.channel,
                    "--out", str(bench / "refused")]) == 1
        # with the ECU's own settings it runs, waiting each cycle for the requests that ECU sends (no stall
        # for a SteeringOverride that a longitudinal ECU never sends)
        own = ClosedLoop(load_scenario(bench / "p.toml"), _fmu(), "tightening",
                         ecu=EcuOptions(mode="attach", channel=ecu.channel, ecu_settings="ecu")).run()
    finally:
        ecu.stop()
    assert own.error is None and own.ecu_settings["settings"]["equipment"] == "longitudinal"
    assert not any(f.arbitration_id == 0x094 for f in own.frames)
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "runs other settings than the scenario's [ecu]" in err and "with equipment 'longitudinal' instead of " \
        "this scene's 'planar_steering' (state equipment = 'planar_steering' in the [ecu] crd ecu reads)" in err
    (bench / "p.toml").write_text(planar.replace("peak_decel_mps2 = 6.5", 'peak_decel_mps2 = 6.5\nequipment = '
                                                                          '"planar_steering"'))
    ecu = Ecu(bench, "--config", str(bench / "p.toml"))
    try:
        attached = ClosedLoop(load_scenario(bench / "p.toml"), _fmu(), "tightening",
                              ecu=EcuOptions(mode="attach", channel=ecu.channel)).run()
    finally:
        ecu.stop()
    assert process_gone(ecu.proc.pid) and attached.error is None
    _same_run(attached, run_scenario(load_scenario(bench / "p.toml"), _fmu(), "tightening"))
    names = {LAYOUTS_BY_ID[f.arbitration_id].name for f in attached.frames if f.arbitration_id in LAYOUTS_BY_ID}
    assert {"EscDynamics", "SteeringOverride", *TRACK_SLOTS} <= names
