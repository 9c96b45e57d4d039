"""Sweep files, key paths and designs (no Dask): strict loading, one-line errors, the design's values."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from cosim.cli.main import main
from cosim.errors import ConfigError
from cosim.sweep import keypath
from cosim.sweep.design import design, inverse_cdf, unit_samples
from cosim.sweep.plan import make_plan
from cosim.sweep.spec import Axis, bundled_sweeps, load_sweep, sweep_from_dict

DATA = Path(__file__).resolve().parent / "sweep_data"
BASE = DATA / "short_cyclist.toml"


def _spec(text: str, tmp_path: Path):
    path = tmp_path / "s.toml"
    path.write_text(f'[sweep]\nscenario = "{BASE}"\n' + text)
    return load_sweep(path)


def test_keypath_parse_and_list_indices() -> None:
    assert keypath.parse("objects[0].speed_mps") == ("objects", 0, "speed_mps")
    assert keypath.render(("a", 2, 1, "b")) == "a[2][1].b"
    schema = {"objects": [{"speed_mps": 1.0}, {"speed_mps": 2.0}], "plant": {"road_friction": 1.0}}
    assert keypath.check(schema, "objects[1].speed_mps") == 2.0
    with pytest.raises(ConfigError, match=r"^objects\[2\]: index out of range; objects has 2 entries$"):
        keypath.check(schema, "objects[2].speed_mps")
    with pytest.raises(ConfigError, match=r"^objects\[0\].sped_mps: unknown key; did you mean objects\[0\].speed_mps\?$"):
        keypath.check(schema, "objects[0].sped_mps")
    mapping = {"objects": [{"speed_mps": 1.0}]}
    keypath.assign(mapping, "objects[0].speed_mps", 5.0)
    keypath.assign(mapping, "plant.parameters.brake_dead_time", 0.2)
    assert mapping == {"objects": [{"speed_mps": 5.0}], "plant": {"parameters": {"brake_dead_time": 0.2}}}


@pytest.mark.parametrize("path, expected", [
    ("plant.road_fricton", "plant.road_fricton: unknown key; did you mean plant.road_friction?"),
    ("plant.parameters.brake_dead_tme",
     "plant.parameters.brake_dead_tme: unknown key; did you mean plant.parameters.brake_dead_time?"),
    ("ecu.peak_decel", "ecu.peak_decel: unknown key; did you mean ecu.peak_decel_mps2?"),
    ("object[0].speed_mps", "object[0]: expected a list to index, object is a table"),
])
def test_bad_key_path_is_one_line_error_naming_file_and_key(tmp_path, capsys, path, expected) -> None:
    sweep = tmp_path / "bad.toml"
    sweep.write_text(f'[sweep]\nscenario = "{BASE}"\n[[axis]]\npath = "{path}"\nvalues = [0.5, 0.6]\n')
    assert main(["sweep", str(sweep), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("error: ")
    assert err == f"error: {sweep}: axis[0].path: {expected}\n"
    assert not (tmp_path / "out").exists()  # nothing ran


def test_sweep_file_rejects_unknown_keys_and_bad_axes(tmp_path) -> None:
    with pytest.raises(ConfigError, match=r"s.toml: axis\[0\].distribuion: unknown key; did you mean axis\[0\].distribution\?$"):
        _spec('[[axis]]\npath = "radar.latency_s"\ndistribuion = "uniform"\n', tmp_path)
    with pytest.raises(ConfigError, match=r"sweep.mode: expected one of"):
        _spec('mode = "random"\n[[axis]]\npath = "radar.latency_s"\nvalues = [0.1]\n', tmp_path)
    with pytest.raises(ConfigError, match=r"distributions need mode = 'monte_carlo'"):
        _spec('[[axis]]\npath = "radar.latency_s"\ndistribution = "uniform"\nlow = 0.0\nhigh = 0.2\n', tmp_path)
    with pytest.raises(ConfigError, match=r"truncated_normal.*missing \['low', 'high'\]"):
        _spec('mode = "monte_carlo"\nsamples = 4\n[[axis]]\npath = "radar.latency_s"\n'
              'distribution = "truncated_normal"\nmean = 0.1\nstd = 0.1\n', tmp_path)
    with pytest.raises(ConfigError, match=r"scenario.seed is set per run"):
        _spec('[[axis]]\npath = "scenario.seed"\nvalues = [1, 2]\n', tmp_path)


def test_range_is_counted_not_accumulated(tmp_path) -> None:
    spec = _spec('[[axis]]\npath = "plant.road_friction"\nstart = 0.3\nstop = 1.0\nstep = 0.1\n', tmp_path)
    assert spec.axes[0].values == (0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)


def test_inverse_cdfs() -> None:
    assert inverse_cdf(Axis("x", distribution="uniform", low=2.0, high=4.0), 0.25) == pytest.approx(2.5)
    assert inverse_cdf(Axis("x", distribution="normal", mean=1.0, std=2.0), 0.975) == pytest.approx(1 + 2 * 1.959964, 1e-5)
    tn = Axis("x", distribution="truncated_normal", mean=0.0, std=1.0, low=0.0, high=1.0)
    # median of N(0,1) truncated to [0, 1]: Φ⁻¹((Φ(0) + Φ(1)) / 2)
    assert inverse_cdf(tn, 0.5) == pytest.approx(0.44177, abs=1e-4)  # Φ⁻¹(0.670672)
    assert 0.0 <= inverse_cdf(tn, 1e-15) and inverse_cdf(tn, 1 - 1e-15) <= 1.0
    ch = Axis("x", values=("a", "b", "c"), distribution="choice", weights=(1.0, 0.0, 3.0))
    assert [inverse_cdf(ch, u) for u in (0.1, 0.3, 0.9)] == ["a", "c", "c"]


def test_latin_hypercube_puts_one_sample_in_each_stratum() -> None:
    u = unit_samples(50, 3, np.random.default_rng(4), latin_hypercube=True)
    for j in range(3):
        assert sorted(np.floor(u[:, j] * 50).astype(int)) == list(range(50))
    plain = unit_samples(50, 3, np.random.default_rng(4), latin_hypercube=False)
    assert any(len(set(np.floor(plain[:, j] * 50).astype(int))) < 50 for j in range(3))


def test_designs_grid_monte_carlo_one_at_a_time(tmp_path) -> None:
    axes = '[[axis]]\npath = "plant.road_friction"\nvalues = [0.5, 1.0]\n' \
           '[[axis]]\npath = "ecu.strategy"\nvalues = ["none", "tightening"]\n'
    grid = design(_spec(axes + '[[axis]]\npath = "radar.latency_s"\nvalues = [0.0, 0.1, 0.2]\n', tmp_path), {})
    assert len(grid) == 12 and grid[0].as_dict() == {"plant.road_friction": 0.5, "ecu.strategy": "none",
                                                      "radar.latency_s": 0.0}
    mc_spec = _spec('mode = "monte_carlo"\nsamples = 5\nlatin_hypercube = true\nseed = 9\n' + axes +
                    '[[axis]]\npath = "radar.latency_s"\ndistribution = "uniform"\nlow = 0.0\nhigh = 0.2\n', tmp_path)
    mc = design(mc_spec, {})
    assert len(mc) == 5 * 4
    draws = sorted({p.as_dict()["radar.latency_s"] for p in mc})
    assert len(draws) == 5 and all(0.0 <= d <= 0.2 for d in draws)
    assert design(mc_spec, {}) == mc  # a function of the sweep file
    oat = _spec('mode = "one_at_a_time"\n[[axis]]\npath = "plant.road_friction"\nvalues = [0.5, 1.0]\n'
                '[[axis]]\npath = "radar.latency_s"\nvalues = [0.0, 0.2]\n'
                '[[axis]]\npath = "ecu.strategy"\nvalues = ["none", "tightening"]\ncross = true\n', tmp_path)
    points = design(oat, {"plant.road_friction": 1.0, "radar.latency_s": 0.1, "ecu.strategy": "tightening"})
    settings = [(p.as_dict()["plant.road_friction"], p.as_dict()["radar.latency_s"]) for p in points[::2]]
    assert settings == [(1.0, 0.1), (0.5, 0.1), (1.0, 0.0), (1.0, 0.2)]


def test_plan_keys_and_seeds_depend_on_the_scenario_not_the_position(tmp_path) -> None:
    a = make_plan(_spec('[[axis]]\npath = "plant.road_friction"\nvalues = [0.5, 0.7, 1.0]\n', tmp_path))
    b = make_plan(_spec('[[axis]]\npath = "plant.road_friction"\nvalues = [1.0, 0.5]\n', tmp_path))
    by_a = {r.point.as_dict()["plant.road_friction"]: (r.key, r.seed) for r in a.runs}
    by_b = {r.point.as_dict()["plant.road_friction"]: (r.key, r.seed) for r in b.runs}
    assert by_a[1.0] == by_b[1.0] and by_a[0.5] == by_b[0.5]
    assert len({s for _, s in by_a.values()}) == 3
    assert all(r.scenario["scenario"]["seed"] == r.seed and r.scenario["plant"]["road_friction"] ==
               r.point.as_dict()["plant.road_friction"] for r in a.runs)
    reseeded = make_plan(_spec('seed = 2\n[[axis]]\npath = "plant.road_friction"\nvalues = [0.5]\n', tmp_path))
    assert reseeded.runs[0].seed != by_a[0.5][1]


def test_bundled_sweeps_load_and_friction_lag_latency_has_1000_runs() -> None:
    assert {"paper_sensitivity", "friction_lag_latency"} <= set(bundled_sweeps())
    spec = load_sweep("friction_lag_latency")
    n = int(np.prod([len(a.values) for a in spec.axes]))
    assert n >= 1000
    assert tomllib.loads(bundled_sweeps()["paper_sensitivity"].read_text())["sweep"]["mode"] == "one_at_a_time"
    assert sweep_from_dict  # the loader is public


def test_list_names_the_bundled_sweeps(capsys) -> None:
    assert main(["sweep", "--list"]) == 0
    out = capsys.readouterr().out
    assert "friction_lag_latency" in out and "paper_sensitivity" in out and "one_at_a_time" in out


def test_axis_into_an_array_of_tables(tmp_path) -> None:
    base = tmp_path / "two.toml"
    base.write_text('[scenario]\nduration_s = 2.0\n[[objects]]\nposition_m = 80.0\n'
                    '[[objects]]\nposition_m = 120.0\nspeed_mps = 5.0\n')
    sweep = tmp_path / "s.toml"
    sweep.write_text(f'[sweep]\nscenario = "{base}"\n[[axis]]\npath = "objects[1].speed_mps"\nvalues = [2, 8.0]\n')
    plan = make_plan(load_sweep(sweep))
    assert plan.base_values == {"objects[1].speed_mps": 5.0}
    from cosim.scenarios.loader import scenario_from_dict

    speeds = [scenario_from_dict(r.scenario).objects[1].speed_mps for r in plan.runs]
    assert speeds == [2.0, 8.0] and [r.point.as_dict()["objects[1].speed_mps"] for r in plan.runs] == [2.0, 8.0]
    sweep.write_text(f'[sweep]\nscenario = "{base}"\n[[axis]]\npath = "objects[2].speed_mps"\nvalues = [1.0]\n')
    with pytest.raises(ConfigError, match=r"s.toml: axis\[0\].path: objects\[2\]: index out of range; objects has 2 entries$"):
        make_plan(load_sweep(sweep))
