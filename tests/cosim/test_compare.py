"""``crd compare`` (issue 24, item 6): two single-run directories pair whatever their strategies,
and nothing compared is an error, never "identical"."""

from __future__ import annotations

import json
import shutil

import pytest

from cosim.cli.main import main as crd
from cosim.loop.experiment import run_strategies
from cosim.results.compare import differences
from cosim.results.run_dir import load_run_dir
from cosim.scenarios.loader import scenario_from_dict

SHORT = {"scenario": {"duration_s": 5.0}, "object": {"position_m": 30.0, "name": "cyclist"}}


def _merged(root, name: str, parts: list[str]) -> None:
    """A directory of several runs, as ``crd paper`` writes it, from single-run directories."""
    runs = []
    for part in parts:
        metrics = json.loads((root / part / "metrics.json").read_text())
        runs += metrics["runs"]
        shutil.copytree(root / part / metrics["runs"][0]["strategy"], root / name / metrics["runs"][0]["strategy"])
    (root / name / "metrics.json").write_text(json.dumps(metrics | {"runs": runs}))


@pytest.fixture(scope="module")
def dirs(tmp_path_factory):
    """Run directories: one run each of four strategies, and two of two strategies each."""
    root = tmp_path_factory.mktemp("compare")
    scenario = scenario_from_dict(SHORT)
    for name in ("tightening", "none", "conservative", "adaptive"):
        run_strategies(scenario, [name], root / name)
    _merged(root, "pair1", ["none", "conservative"])
    _merged(root, "pair2", ["tightening", "adaptive"])
    return root


def _metrics(path) -> dict:
    return json.loads((path / "metrics.json").read_text())["runs"][0]


def test_single_runs_of_different_strategies_pair(dirs, capsys):
    assert crd(["compare", str(dirs / "tightening"), str(dirs / "none"), "--out", str(dirs / "cmp")]) == 0
    out = capsys.readouterr().out
    assert "only in" not in out and "identical" not in out
    a, b = _metrics(dirs / "tightening"), _metrics(dirs / "none")
    row = next(line for line in out.splitlines() if "contingency invocations" in line).split()
    assert row[-3:-1] == [str(a["contingency_invocations"]), str(b["contingency_invocations"])]
    assert next(line for line in out.splitlines() if "collided" in line).startswith("tightening | none")
    assert "of 7 metrics differ (wall time aside)" in out
    assert (dirs / "cmp" / "speed_profiles.png").stat().st_size > 20_000


def test_nothing_paired_is_an_error_not_identical(dirs, capsys):
    assert crd(["compare", str(dirs / "pair1"), str(dirs / "pair2"), "--out", str(dirs / "cmp2")]) == 1
    captured = capsys.readouterr()
    assert "identical" not in captured.out
    err = captured.err.strip()
    assert err == (f"error: nothing to compare: {dirs / 'pair1'} holds none, conservative; {dirs / 'pair2'} holds "
                   "tightening, adaptive (runs pair by strategy, or one run with one)")
    assert not (dirs / "cmp2").exists()


def test_runs_of_several_strategies_pair_by_strategy(dirs):
    lines = differences(load_run_dir(dirs / "pair1"), load_run_dir(dirs / "none"))
    assert [line.split()[0] for line in lines if "collided" in line] == ["none"]
    assert "only in A: conservative" in lines
    assert lines[-1] == "identical in all 7 metrics (wall time aside)"  # the same run, written twice


def test_the_object_is_named_from_the_run(dirs):
    run = load_run_dir(dirs / "tightening")
    assert (run.object_name, run.object_position_m) == ("cyclist", 30.0)
