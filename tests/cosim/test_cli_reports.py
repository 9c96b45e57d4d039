"""The CLI and the reports (issue 13, findings 6 and 8): --version, bundled scenarios by name,
report.md with rounded numbers, crd compare, and the warning for derived wheel speeds."""

import json
import re
from importlib.metadata import version

import pytest

from cosim.cli.main import main as crd
from cosim.cli.scenarios import BUNDLED_DIR, find_scenario
from cosim.loop.experiment import run_strategies
from cosim.results.paper_claims import evaluate
from cosim.results.run_record import RunMetrics, RunRecord
from cosim.scenarios.loader import scenario_from_dict

SHORT = '[scenario]\nduration_s = {d}\n[object]\nposition_m = {p}\n[ecu]\nstrategy = "conservative"\n' \
        '[checks]\nno_collision = true\nmin_gap_m = 0.5\n'
RAW_FLOAT = re.compile(r"\d\.\d{4,}")  # a number printed with more digits than it means


def test_version(capsys):
    with pytest.raises(SystemExit) as done:
        crd(["--version"])
    assert done.value.code == 0
    assert capsys.readouterr().out.strip() == f"crd {version('crd')}"


def test_scenarios_lists_the_bundled_files(capsys):
    assert crd(["scenarios"]) == 0
    out = capsys.readouterr().out
    names = [p.stem for p in BUNDLED_DIR.glob("*.toml")]
    assert "paper_cyclist" in names
    for name in names:
        assert re.search(rf"^{name}\s+\d", out, re.M), name
    assert "The paper's experiment (Johnson 2019, section III)" in out


def test_run_finds_a_bundled_scenario_by_name(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # no such file here: the name must resolve to the bundled one
    assert find_scenario("paper_cyclist.toml") == find_scenario("paper_cyclist") == BUNDLED_DIR / "paper_cyclist.toml"
    (tmp_path / "paper_cyclist.toml").write_text("[scenario]\n")
    assert find_scenario("paper_cyclist.toml").resolve() == tmp_path / "paper_cyclist.toml"  # a file given wins
    (tmp_path / "paper_cyclist.toml").unlink()
    assert crd(["run", "paper_cyclist", "--strategy", "none", "--out", "o"]) == 0
    assert "paper_cyclist.toml (strategy none)" in capsys.readouterr().err
    runs = json.loads((tmp_path / "o" / "metrics.json").read_text())["runs"]
    assert runs[0]["collided"] and runs[0]["impact_speed_mps"] == pytest.approx(4.28, abs=0.01)


def test_unknown_scenario_name_is_one_line(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert crd(["run", "paper_cyclst"]) == 1
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("error: paper_cyclst: scenario file not found")
    bundled = err.split("(bundled: ")[1].split(";")[0].split(", ")
    assert bundled == [p.stem for p in sorted(BUNDLED_DIR.glob("*.toml"))] and "paper_cyclist" in bundled
    assert "lane_change_parked_car" in bundled


def test_run_writes_report_md(tmp_path):
    (tmp_path / "s.toml").write_text(SHORT.format(d=6.0, p=40.0))
    assert crd(["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o")]) == 0
    report = (tmp_path / "o" / "report.md").read_text()
    metrics = json.loads((tmp_path / "o" / "metrics.json").read_text())["runs"][0]
    assert f"| conservative | no | - | {metrics['min_gap_m']:.2f} |" in report
    assert "**PASS** no_collision (conservative)" in report
    assert f"**PASS** min_gap_m (conservative)  \n  min_gap_m: expected >= 0.5 m, got {metrics['min_gap_m']:.2f} m" \
        in report
    for png in re.findall(r"!\[[^]]*\]\(([^)]+)\)", report):
        assert (tmp_path / "o" / png).is_file(), png
    assert {"speed_profiles.png", "conservative/timeline.png"} <= set(re.findall(r"\]\(([^)]+\.png)\)", report))
    resolved = (tmp_path / "o" / "config.resolved.toml").read_text()
    assert resolved.strip() in report
    tables = [line for line in report.splitlines() if line.startswith("| conservative")]
    assert tables and not RAW_FLOAT.search(tables[0])
    events = json.loads((tmp_path / "o" / "conservative" / "events.json").read_text())["events"]
    assert not [e for e in events if e["kind"] == "warning"]  # the builtin plant has wheel speeds
    assert "ABS wheel slip" not in report


def test_claim_details_are_rounded():
    def record(strategy, collided, gap, speeds):
        m = RunMetrics(strategy, collided, 4.2813519199527015 if collided else None, gap, None if collided else gap,
                       5, 30.123456789, 40.0)
        rows = [(i * 0.01, float(x), v, 0.0, 0.0, 0.0, "CONTINGENCY", 0.0, 100.0, 0.0)
                for i, (x, v) in enumerate(zip(range(0, 230), speeds))]
        return RunRecord(strategy, m, rows)

    records = [record("none", True, -0.0003, [10.0] * 230), record("conservative", False, 1.9409319708533417,
                                                                  [9.0] * 230),
               record("tightening", False, 3.3148540164395683, [9.5] * 200 + [8.0] * 30)]
    details = {c.number: c.detail for c in evaluate(records)}
    assert "impact 4.28 m/s" in details["1"]
    assert "final gap 1.94 m" in details["2"] and "final gap 3.31 m" in details["2"]
    assert details["5"] == "final gap: tightening 3.31 m, conservative 1.94 m"
    for detail in details.values():
        assert not RAW_FLOAT.search(detail), detail


def test_compare_prints_differences_and_overlays(tmp_path, capsys):
    for name, position in (("a", 40.0), ("b", 45.0)):
        (tmp_path / f"{name}.toml").write_text(SHORT.format(d=7.0, p=position))
        assert crd(["run", str(tmp_path / f"{name}.toml"), "--out", str(tmp_path / name)]) == 0
    capsys.readouterr()
    assert crd(["compare", str(tmp_path / "a"), str(tmp_path / "b"), "--out", str(tmp_path / "cmp")]) == 0
    out = capsys.readouterr().out
    a, b = (json.loads((tmp_path / n / "metrics.json").read_text())["runs"][0] for n in ("a", "b"))
    row = next(line for line in out.splitlines() if "max speed (m/s)" in line).split()
    assert row[-3:] == [f"{a['max_speed_mps']:.2f}", f"{b['max_speed_mps']:.2f}",
                        f"{round(b['max_speed_mps'], 2) - round(a['max_speed_mps'], 2):+.2f}"]
    assert b["max_speed_mps"] > a["max_speed_mps"]  # 5 m more run-up
    assert "metrics differ (wall time aside)" in out
    assert (tmp_path / "cmp" / "speed_profiles.png").stat().st_size > 20_000
    assert crd(["compare", str(tmp_path / "a"), str(tmp_path / "a"), "--out", str(tmp_path / "cmp")]) == 0
    assert "identical in all 7 metrics (wall time aside)" in capsys.readouterr().out


def test_compare_refuses_a_directory_without_metrics(tmp_path, capsys):
    assert crd(["compare", str(tmp_path), str(tmp_path)]) == 1
    assert "not a crd run directory" in capsys.readouterr().err


FIXTURE_PLANT = {  # position and speed only: the wheel speeds are derived from the speed
    "accel_gain_mps2": 3.0, "brake_gain_mps2": 12.0,
    "inputs": {"accel_command": "a_cmd"},
    "outputs": {"position": "s_m", "speed": {"name": "speed_kmh", "scale": 1 / 3.6}},
}


def test_derived_wheel_speeds_warn_in_events_and_report(point_mass_fmu, tmp_path):
    sc = scenario_from_dict({"scenario": {"duration_s": 1.0},
                             "plant": dict(FIXTURE_PLANT, fmu=str(point_mass_fmu))})
    run_strategies(sc, ["conservative"], tmp_path)
    events = json.loads((tmp_path / "conservative" / "events.json").read_text())["events"]
    warnings = [e for e in events if e["kind"] == "warning"]
    assert len(warnings) == 1 and "ABS wheel slip is invisible to the ECU" in warnings[0]["detail"]
    assert "ABS wheel slip is invisible to the ECU" in (tmp_path / "report.md").read_text()

