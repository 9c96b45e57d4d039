"""``crd sweep`` over a fleet scene (issue 23 item 8): axis paths into the fleet file, the dance columns, the
same rows on one worker and on two, one-line errors for a bad path, the maps of collision rate and deadlock.

The Dask part runs 4 short crossings with human drivers (8 s simulated) twice: about 30 s on 2 cores.
"""

from __future__ import annotations

from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from tests.loopback import loopback_only  # noqa: F401 - autouse: every socket to loopback

from cosim.cli.main import main
from cosim.errors import ConfigError
from cosim.sweep.maps import cell_grid, levels
from cosim.sweep.plan import make_plan
from cosim.sweep.runner import ClusterOptions
from cosim.sweep.session import run_sweep
from cosim.sweep.spec import SUBJECT_KINDS, bundled_sweeps, load_sweep
from cosim.sweep.subjects import SUBJECTS
from cosim.sweep.table import read_results
from cosim.sweep.task import cached_fmu, run_one
from cosim.world.fmu_share import file_sha256

SMALL = """
[sweep]
name = "small_dance"
fleet = "crossing_reacting"
seed = 3

[[axis]]
path = "fleet.duration_s"
values = [8.0]

[[axis]]
path = "vehicles[1].y_m"
values = [-40.0, -48.333]

[[axis]]
path = "vehicle.ecu.strategy"
values = ["none", "tightening"]
"""
DANCE_COLUMNS = {"collisions": pa.int64(), "collided": pa.bool_(), "impact_speed_mps": pa.float64(),
                 "deadlock_s": pa.float64(), "time_to_clear_s": pa.float64(), "all_cleared": pa.bool_(),
                 "min_decelerations": pa.int64(), "contingency_invocations": pa.int64()}


def _sweep(tmp: Path, text: str, name: str = "sweep.toml") -> Path:
    path = tmp / name
    path.write_text(text)
    return path


def _rows(out: Path) -> list[dict]:
    return [{k: v for k, v in r.items() if k != "task_wall_s"} for r in pq.read_table(out / "results.parquet").to_pylist()]


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("fleet_sweep")
    sweep = _sweep(tmp, SMALL)
    run_sweep(load_sweep(sweep), tmp / "w1", ClusterOptions(workers=1, dashboard=False))
    return sweep, tmp / "w1"


def test_rows_carry_the_dance_figures_and_the_axis_values(small) -> None:
    _, out = small
    table, meta = read_results(out / "results.parquet")
    assert meta["subject"] == "fleet" and meta["strategy_axis"] == "vehicle.ecu.strategy"
    for name, kind in DANCE_COLUMNS.items():
        assert table.schema.field(name).type == kind, name
    rows = table.to_pylist()
    assert [r["status"] for r in rows] == ["ok"] * 4, [r["error"] for r in rows]
    assert {(r["vehicles[1].y_m"], r["strategy"]) for r in rows} == {
        (y, s) for y in (-40.0, -48.333) for s in ("none", "tightening")}
    for r in rows:
        assert r["collided"] == (r["collisions"] > 0) and r["end_time_s"] <= 8.0
        assert (r["impact_speed_mps"] is not None) == r["collided"]
        assert r["all_cleared"] == (r["all_cleared_s"] is not None) and r["deadlock_s"] >= 0.0
    # the scene as crd fleet crossing_reacting knows it: without tightening the simultaneous arrival collides
    same_time = {r["strategy"]: r for r in rows if r["vehicles[1].y_m"] == -40.0}
    assert same_time["none"]["collided"] and not same_time["tightening"]["collided"]


def test_one_worker_two_and_in_process_give_the_same_rows(small, tmp_path) -> None:
    sweep, out1 = small
    run_sweep(load_sweep(sweep), tmp_path / "w2", ClusterOptions(workers=2, dashboard=False), report=False)
    assert _rows(tmp_path / "w2") == _rows(out1)
    plan = make_plan(load_sweep(sweep))
    sha = file_sha256(plan.fmu_path)
    cached_fmu(sha, plan.fmu_path.read_bytes(), tmp_path / "fmu")
    here = {k: v for k, v in run_one(plan.runs[3], sha).items() if k != "task_wall_s"}
    assert here == _rows(out1)[3]


def test_report_maps_collision_rate_and_deadlock(small, tmp_path) -> None:
    _, out = small
    report = (out / "report.md").read_text()
    assert "| strategy | runs |" in report and "runs with deadlock" in report
    assert "collides" in report  # the outcome of each setting, in the fleet's words
    assert not list((out / "maps").glob("*.png"))  # one numeric axis with two values: no pair to map
    copy = tmp_path / "copy"
    copy.mkdir()
    (copy / "results.parquet").write_bytes((out / "results.parquet").read_bytes())
    assert main(["sweep", "report", str(copy), "--axes", "vehicles[1].y_m", "fleet.duration_s"]) == 0
    assert sorted(p.name.split("__")[0] for p in (copy / "maps").glob("*.png")) == ["collision_rate", "mean_deadlock_s"]
    assert "### mean time in deadlock (s): `vehicles[1].y_m` × `fleet.duration_s`" in (copy / "report.md").read_text()
    rows = pq.read_table(out / "results.parquet").to_pylist()
    x, y = levels([r["vehicles[1].y_m"] for r in rows]), levels([r["fleet.duration_s"] for r in rows])
    for strategy in ("none", "tightening"):
        mine = {r["vehicles[1].y_m"]: r for r in rows if r["strategy"] == strategy}
        deadlock = cell_grid(rows, strategy, x, y, "mean_deadlock_s")
        collided = cell_grid(rows, strategy, x, y, "collision_rate")
        assert deadlock.tolist() == [[mine[-48.333]["deadlock_s"], mine[-40.0]["deadlock_s"]]]
        assert collided.tolist() == [[float(mine[-48.333]["collided"]), float(mine[-40.0]["collided"])]]


@pytest.mark.parametrize("path, expected", [
    ("vehicle.ecu.way_ot", "axis[0].path: vehicle.ecu.way_ot: unknown key; did you mean vehicle.ecu.way_out?"),
    ("vehicles[2].y_m", "axis[0].path: vehicles[2]: index out of range; vehicles has 2 entries"),
    ("vehicles[1].y", "axis[0].path: vehicles[1].y: unknown key; expected one of name, x_m, y_m, heading_rad, "
                      "plant, driver, ecu, radar, gateway, road, end"),
    ("fleet.sed", "axis[0].path: fleet.sed: unknown key; did you mean fleet.seed?"),
])
def test_bad_fleet_key_path_is_one_line_error_naming_it(tmp_path, capsys, path, expected) -> None:
    sweep = _sweep(tmp_path, f'[sweep]\nfleet = "crossing"\n[[axis]]\npath = "{path}"\nvalues = [1.0, 2.0]\n', "bad.toml")
    assert main(["sweep", str(sweep), "--out", str(tmp_path / "out")]) == 1
    assert capsys.readouterr().err == f"error: {sweep}: {expected}\n"
    assert not (tmp_path / "out").exists()  # nothing ran


def test_also_paths_take_the_axis_value_and_are_checked(tmp_path) -> None:
    text = ('[sweep]\nfleet = "crossing"\n[[axis]]\npath = "vehicle.plant.initial_speed_mps"\n'
            'also = ["vehicle.driver.set_speed_mps"]\nvalues = [8.333, 11]\n')
    plan = make_plan(load_sweep(_sweep(tmp_path, text)))
    speeds = [(r.scenario["vehicle"]["plant"]["initial_speed_mps"], r.scenario["vehicle"]["driver"]["set_speed_mps"])
              for r in plan.runs]
    assert speeds == [(8.333, 8.333), (11.0, 11.0)]
    assert [r.point.values for r in plan.runs] == [(("vehicle.plant.initial_speed_mps", v),) for v in (8.333, 11.0)]
    bad = _sweep(tmp_path, text.replace("set_speed_mps", "set_sped_mps"), "bad.toml")
    with pytest.raises(ConfigError, match=r"axis\[0\]\.also: vehicle\.driver\.set_sped_mps: unknown key; did you mean "
                                          r"vehicle\.driver\.set_speed_mps\?$"):
        make_plan(load_sweep(bad))


def test_fleet_seed_is_derived_per_run_unless_it_is_an_axis(tmp_path) -> None:
    derived = make_plan(load_sweep(_sweep(tmp_path, SMALL)))
    seeds = [r.seed for r in derived.runs]
    assert len(set(seeds)) == 4 and all(0 <= s < 2**62 for s in seeds)
    assert all(r.scenario["fleet"]["seed"] == r.seed for r in derived.runs)
    given = make_plan(load_sweep(_sweep(tmp_path, SMALL + '[[axis]]\npath = "fleet.seed"\nvalues = [1, 2]\n', "s2.toml")))
    assert sorted({r.seed for r in given.runs}) == [1, 2] and len(given.runs) == 8
    assert all(r.scenario["fleet"]["seed"] == r.seed for r in given.runs)
    repeated = _sweep(tmp_path, SMALL.replace("seed = 3", "seed = 3\nreplicates = 2")
                      + '[[axis]]\npath = "fleet.seed"\nvalues = [1, 2]\n', "s3.toml")
    with pytest.raises(ConfigError, match="every replicate would repeat the same run"):
        make_plan(load_sweep(repeated))
    hidden = _sweep(tmp_path, SMALL.replace('path = "fleet.duration_s"', 'path = "fleet.duration_s"\nalso = ["fleet.seed"]'),
                    "s4.toml")
    with pytest.raises(ConfigError, match=r"axis\[0\]\.also: fleet\.seed is a run's seed"):
        make_plan(load_sweep(hidden))


def test_a_value_the_fleet_loader_refuses_fails_its_run_only(tmp_path) -> None:
    """A heading out of range: the plan takes it (the path is good), the run is a failed row naming the key."""
    text = '[sweep]\nfleet = "crossing"\n[[axis]]\npath = "vehicles[1].heading_rad"\nvalues = [1.5707963267948966, 99.0]\n'
    plan = make_plan(load_sweep(_sweep(tmp_path, text)))
    sha = file_sha256(plan.fmu_path)
    cached_fmu(sha, plan.fmu_path.read_bytes(), tmp_path / "fmu")
    row = run_one(plan.runs[1], sha)
    assert row["status"] == "failed" and row["collisions"] is None and row["vehicles[1].heading_rad"] == 99.0
    assert "vehicles[1].heading_rad" in row["error"]


def test_base_is_one_of_scenario_or_fleet_and_the_registry_knows_each(tmp_path) -> None:
    assert set(SUBJECT_KINDS) == set(SUBJECTS)
    both = '[sweep]\nfleet = "crossing"\nscenario = "paper_cyclist"\n[[axis]]\npath = "fleet.seed"\nvalues = [1]\n'
    with pytest.raises(ConfigError, match=r"sweep: expected one base, scenario or fleet; got \['scenario', 'fleet'\]"):
        load_sweep(_sweep(tmp_path, both))
    with pytest.raises(ConfigError, match=r"sweep\.fleet: expected a fleet file or a bundled fleet name \(crossing, "):
        load_sweep(_sweep(tmp_path, '[sweep]\nfleet = "crosing"\n[[axis]]\npath = "fleet.seed"\nvalues = [1]\n'))
    with pytest.raises(ConfigError, match="--keep-timeseries: a fleet sweep keeps no time series"):
        run_sweep(load_sweep(_sweep(tmp_path, SMALL)), tmp_path / "out", ClusterOptions(workers=1), keep_timeseries=True)


def test_bundled_crossing_dance_plans_40_runs() -> None:
    plan = make_plan(load_sweep(bundled_sweeps()["crossing_dance"]))
    assert len(plan.runs) == 40 and plan.spec.subject == "fleet"
    offsets_s = sorted({round((-40.0 - r.point.as_dict()["vehicles[1].y_m"]) / 8.333, 2) for r in plan.runs})
    assert offsets_s == [0.0, 0.5, 1.0, 1.5, 2.0]
    assert all(r.scenario["vehicle"]["plant"]["initial_speed_mps"] == r.scenario["vehicle"]["driver"]["set_speed_mps"]
               for r in plan.runs)
