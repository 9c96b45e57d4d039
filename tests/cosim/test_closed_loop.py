"""Closed-loop runs: determinism, third-party FMU, FMI failure mid-run, CAN logs, CLI exit codes."""

import json
import subprocess
import sys
from datetime import datetime

import can
import cantools
import pytest

from can_dbc import AUTHENTICATORS, DBC_PATH, generate_key, write_key_file
from cosim.cli.main import main as crd
from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import run_strategies
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import run_scenario
from cosim.scenarios.config import DEFAULT_START_TIME
from cosim.scenarios.loader import load_scenario, scenario_from_dict

SHORT = {"scenario": {"duration_s": 7.0, "seed": 3},
         "object": {"position_m": 40.0},
         "radar": {"range_noise_std_m": 0.2, "range_rate_noise_std_mps": 0.1}}

FIXTURE_PLANT = {
    "accel_gain_mps2": 3.0, "brake_gain_mps2": 12.0,  # = gateway brake_full_decel_mps2
    "inputs": {"accel_command": "a_cmd"},
    "outputs": {"position": "s_m", "speed": {"name": "speed_kmh", "scale": 1 / 3.6}, "accel": "a_act"},
}


def test_two_runs_are_identical(plant_fmu3, tmp_path):
    """Bit for bit under one SecOC key; with the default fresh key per run only the MACs differ."""
    sc = scenario_from_dict(SHORT)
    key_file = str(write_key_file(tmp_path / "run.key", generate_key()))
    a, b = (run_scenario(sc, plant_fmu3, "none", ecu=EcuOptions(key_file=key_file)) for _ in range(2))
    da, db = a.metrics.as_dict(), b.metrics.as_dict()
    da.pop("wall_time_s"), db.pop("wall_time_s")
    assert da == db
    assert a.rows == b.rows and a.frames == b.frames
    assert a.metrics.contingency_invocations >= 1  # the object at 40 m does engage the ECU
    fresh = run_scenario(sc, plant_fmu3, "none")
    auth_ids = set(AUTHENTICATORS.values())
    assert fresh.rows == a.rows
    assert [f for f in fresh.frames if f.arbitration_id not in auth_ids] == \
        [f for f in a.frames if f.arbitration_id not in auth_ids]


def test_fmu_error_mid_run_keeps_results(point_mass_fmu, tmp_path):
    plant = dict(FIXTURE_PLANT, fmu=str(point_mass_fmu), parameters={"fail_at": 1.5})
    sc = scenario_from_dict({"scenario": {"duration_s": 5.0}, "plant": plant})
    rec = run_strategies(sc, ["conservative"], tmp_path)[0]
    assert rec.error and "t = 1.500000 s" in rec.error and "fmi2Discard" in rec.error
    metrics = json.loads((tmp_path / "metrics.json").read_text())["runs"][0]
    assert metrics["sim_time_s"] == pytest.approx(1.5) and metrics["error"] == rec.error
    lines = (tmp_path / "conservative" / "timeseries.csv").read_text().splitlines()
    assert len(lines) == 1 + 151  # header + one row per 10 ms cycle, 0 s .. 1.5 s inclusive


def test_paper_scenario_through_fixture_fmu(point_mass_fmu, tmp_path):
    """A different-shaped FMU (acceleration input, km/h, other names) runs the paper scenario."""
    data = {"scenario": {"duration_s": 30.0}, "plant": dict(FIXTURE_PLANT, fmu=str(point_mass_fmu)),
            "object": {"position_m": 225.0}, "ecu": {"strategy": "conservative"}}
    rec = run_scenario(scenario_from_dict(data), point_mass_fmu)
    assert rec.error is None
    assert rec.metrics.max_speed_mps > 20.0  # it really drove
    assert rec.metrics.contingency_invocations >= 1
    assert not rec.metrics.collided and rec.metrics.final_gap_m > 0.0


@pytest.mark.slow
def test_paper_scenario_through_fmi3_build(tmp_path):
    sc = load_scenario(PAPER_SCENARIO)
    assert sc.plant.fmi_version == 3
    recs = run_strategies(sc, ["conservative"], tmp_path)
    assert recs[0].error is None and recs[0].metrics.max_speed_mps > 25.0
    assert recs[0].fmu_path.endswith(".fmu") and len(recs[0].fmu_sha256) == 64
    for name in ("metrics.json", "config.resolved.toml", "speed_profiles.png",
                 "conservative/timeseries.csv", "conservative/can.blf", "conservative/timeline.png"):
        assert (tmp_path / name).is_file(), name
    again = load_scenario(tmp_path / "config.resolved.toml")  # the resolved file repeats the run
    assert again.scenario == sc.scenario and again.ecu.strategy == "conservative"


@pytest.mark.parametrize("suffix", [".blf", ".asc"])
def test_can_log_readable_and_decodable(tmp_path, suffix):
    scen = tmp_path / "s.toml"
    scen.write_text('[scenario]\nduration_s = 1.0\n[object]\nposition_m = 30.0\n[ecu]\nstrategy = "none"\n')
    assert crd(["run", str(scen), "--out", str(tmp_path / "o"), "--can-log", f"can{suffix}"]) == 0
    log = tmp_path / "o" / "none" / f"can{suffix}"
    msgs = list(can.LogReader(str(log)))
    ids = {m.arbitration_id for m in msgs}
    assert {0x090, 0x0A0, 0x0B0, 0x0C0, 0x3A0} <= ids
    # BLF readers add the header's start time (the scenario's start_time); ASC readers give the offsets
    t0 = datetime.fromisoformat(DEFAULT_START_TIME).timestamp() if suffix == ".blf" else 0.0
    assert msgs[0].timestamp - t0 == pytest.approx(0.0) and msgs[-1].timestamp - t0 == pytest.approx(0.99)
    assert sum(m.arbitration_id == 0x0C0 for m in msgs) == 20  # ObjectTrack every 50 ms
    db = cantools.database.load_file(str(DBC_PATH))
    decoded = db.decode_message(0x0C0, bytes(next(m for m in msgs if m.arbitration_id == 0x0C0).data))
    assert decoded["ObjectValid"] in (1, "VALID") and decoded["ObjectRange"] == pytest.approx(30.0, abs=0.05)
    out = subprocess.run([sys.executable, "-m", "cantools", "decode", "--single-line", str(DBC_PATH)],
                         input="  vcan0  0B0   [8]  " + " ".join(f"{b:02X}" for b in bytes(next(
                             m for m in msgs if m.arbitration_id == 0x0B0).data)) + "\n",
                         capture_output=True, text=True, check=True)
    assert "DriverInput" in out.stdout and "AccelPedal: 100" in out.stdout


def test_crd_run_exit_3_on_failed_check(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text('[scenario]\nduration_s = 6.0\n[object]\nposition_m = 40.0\n'
                    '[ecu]\nstrategy = "conservative"\n[checks]\nmin_gap_m = 100.0\nno_collision = true\n')
    assert crd(["run", str(scen), "--out", str(tmp_path / "o")]) == 3
    assert "CHECK FAILED: min_gap_m: expected >= 100.0 m" in capsys.readouterr().out


def test_crd_run_bad_scenario_is_one_line(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text("[scenario]\nduraton_s = 6.0\n")
    assert crd(["run", str(scen)]) == 1
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err == f"error: {scen}: scenario.duraton_s: unknown key; did you mean scenario.duration_s?"


def test_crd_run_missing_fmu_is_one_line(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text('[plant]\nfmu = "nope.fmu"\n[plant.inputs]\nthrottle = "t"\nbrake = "b"\n'
                    '[plant.outputs]\nposition = "x"\nspeed = "v"\n')
    assert crd(["run", str(scen), "--out", str(tmp_path / "o")]) == 1
    assert "nope.fmu" in capsys.readouterr().err and not (tmp_path / "o").exists()
