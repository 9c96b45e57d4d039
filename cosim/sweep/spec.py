"""Sweep files (TOML) -> :class:`SweepSpec`, strictly.

A sweep file names a base scenario and the axes to vary over it::

    [sweep]
    name = "friction_lag_latency"
    scenario = "paper_cyclist"        # a bundled scenario name, or a path relative to this file
    mode = "grid"                     # "grid" | "monte_carlo" | "one_at_a_time"
    seed = 1                          # the per-run seeds derive from this and each run's key
    samples = 200                     # monte_carlo: number of samples of the distribution axes
    latin_hypercube = false           # monte_carlo: stratify the samples (one per 1/N stratum per axis)
    replicates = 1                    # runs per combination (each with its own seed)

    [[axis]]
    path = "plant.road_friction"      # any key path of the scenario, e.g. objects[0].speed_mps
    start = 0.3                       # a range: start + k * step, k = 0, 1, ... up to stop (inclusive)
    stop = 1.0
    step = 0.1

    [[axis]]
    path = "ecu.strategy"
    values = ["none", "conservative", "tightening"]   # a list

    [[axis]]
    path = "radar.latency_s"
    distribution = "truncated_normal" # "uniform" (low, high), "normal" (mean, std),
    mean = 0.1                        # "truncated_normal" (mean, std, low, high),
    std = 0.05                        # "choice" (values, optional weights)
    low = 0.0
    high = 0.2

Unknown keys and bad values raise :class:`~cosim.errors.ConfigError` naming the
file and the key (``axis[2].distribuion``), with the scenario loader's suggestion.
Whether each axis's path exists in the scenario is checked by
:mod:`cosim.sweep.plan` against the resolved scenario.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Mapping

from ..errors import ConfigError
from ..scenarios.loader import _unknown as unknown_key_error
from ..scenarios.loader import load_toml_file

MODES = ("grid", "monte_carlo", "one_at_a_time")
DISTRIBUTIONS = {  # name -> required parameters (choice also takes optional weights)
    "uniform": ("low", "high"),
    "normal": ("mean", "std"),
    "truncated_normal": ("mean", "std", "low", "high"),
    "choice": ("values",),
}
_SWEEP_KEYS = ("name", "description", "scenario", "mode", "seed", "samples", "latin_hypercube", "replicates")
_AXIS_KEYS = ("path", "values", "start", "stop", "step", "distribution", "low", "high", "mean", "std",
              "weights", "cross")
_MAX_RANGE_POINTS = 100_000


@dataclass(frozen=True)
class Axis:
    """One varied key path: a list of ``values`` (lists and ranges) or a ``distribution``.

    ``cross`` (one_at_a_time mode): cross this axis with every run instead of varying it alone.
    """

    path: str
    values: tuple = ()
    distribution: str | None = None
    low: float | None = None
    high: float | None = None
    mean: float | None = None
    std: float | None = None
    weights: tuple[float, ...] = ()
    cross: bool = False

    @property
    def sampled(self) -> bool:
        return self.distribution is not None


@dataclass(frozen=True)
class SweepSpec:
    """A whole sweep file; ``scenario`` is the resolved path of the base scenario file."""

    name: str
    scenario: Path
    source: Path
    axes: tuple[Axis, ...]
    mode: str = "grid"
    seed: int = 0
    samples: int = 0
    latin_hypercube: bool = False
    replicates: int = 1
    description: str = ""


def bundled_dir() -> Path:
    return Path(str(resources.files("cosim.sweep") / "bundled"))


def bundled_sweeps() -> dict[str, Path]:
    """Bundled sweep name -> file (``cosim/sweep/bundled/*.toml``)."""
    return {p.stem: p for p in sorted(bundled_dir().glob("*.toml"))}


def find_sweep(name_or_path: str | Path) -> Path:
    """A sweep file path, or the file of a bundled sweep name."""
    path = Path(name_or_path)
    if path.suffix == ".toml" or path.exists():
        return path
    found = bundled_sweeps().get(str(name_or_path))
    if found is None:
        raise ConfigError(f"{name_or_path}: no such sweep file, and not a bundled sweep "
                          f"(bundled: {', '.join(bundled_sweeps()) or 'none'})")
    return found


def _base_scenario(value: str, source: Path) -> Path:
    if value.endswith(".toml") or "/" in value:
        path = Path(value)
        return path if path.is_absolute() else (source.parent / path).resolve()
    bundled = Path(str(resources.files("cosim.scenarios") / f"{value}.toml"))
    if not bundled.is_file():
        raise ConfigError(f"sweep.scenario: expected a scenario file or a bundled scenario name, got {value!r}")
    return bundled


def _number(table: Mapping[str, Any], key: str, where: str, integer: bool = False) -> Any:
    value = table[key]
    ok = isinstance(value, int) if integer else isinstance(value, (int, float))
    if isinstance(value, bool) or not ok or (isinstance(value, float) and not math.isfinite(value)):
        raise ConfigError(f"{where}.{key}: expected {'an integer' if integer else 'a finite number'}, got {value!r}")
    return value


def _check_keys(table: Any, valid: tuple[str, ...], where: str) -> None:
    if not isinstance(table, Mapping):
        raise ConfigError(f"{where}: expected a table, got {table!r}")
    for key in table:
        if key not in valid:
            raise unknown_key_error(key, where, valid)


def _range_values(t: Mapping[str, Any], where: str) -> tuple:
    start, stop, step = (_number(t, k, where) for k in ("start", "stop", "step"))
    if step <= 0 or stop < start:
        raise ConfigError(f"{where}: expected step > 0 and stop >= start, got start {start}, stop {stop}, step {step}")
    count = int(math.floor((stop - start) / step + 1e-9)) + 1
    if count > _MAX_RANGE_POINTS:
        raise ConfigError(f"{where}: expected at most {_MAX_RANGE_POINTS} points, got {count}")
    ints = all(isinstance(v, int) for v in (start, stop, step))
    # start + k*step from an integer counter, rounded so 0.1 steps read back as 0.3, not 0.30000000000000004
    return tuple(start + k * step if ints else round(start + k * step, 12) for k in range(count))


def _value_list(values: Any, where: str) -> tuple:
    if not isinstance(values, list) or not values:
        raise ConfigError(f"{where}: expected a non-empty list, got {values!r}")
    kinds = {str if isinstance(v, str) else bool if isinstance(v, bool) else float for v in values}
    if len(kinds) != 1 or any(isinstance(v, (list, dict)) for v in values):
        raise ConfigError(f"{where}: expected values of one kind (numbers, strings or booleans), got {values!r}")
    if len(set(values)) != len(values):
        raise ConfigError(f"{where}: expected distinct values, got {values!r}")
    return tuple(values)


def _distribution(t: Mapping[str, Any], where: str) -> dict[str, Any]:
    name = t["distribution"]
    if name not in DISTRIBUTIONS:
        raise ConfigError(f"{where}.distribution: expected one of {list(DISTRIBUTIONS)}, got {name!r}")
    missing = [k for k in DISTRIBUTIONS[name] if k not in t]
    extra = [k for k in ("low", "high", "mean", "std", "weights", "start", "stop", "step", "values")
             if k in t and k not in DISTRIBUTIONS[name] and not (name == "choice" and k == "weights")]
    if missing or extra:
        raise ConfigError(f"{where}: distribution {name!r} takes {list(DISTRIBUTIONS[name])}"
                          f"{' (+ weights)' if name == 'choice' else ''}; missing {missing}, unexpected {extra}")
    if name == "choice":
        values = _value_list(t["values"], f"{where}.values")
        weights = tuple(float(_number({"w": w}, "w", f"{where}.weights")) for w in t.get("weights", []))
        if weights and (len(weights) != len(values) or min(weights) < 0 or sum(weights) <= 0):
            raise ConfigError(f"{where}.weights: expected {len(values)} non-negative weights, got {list(weights)}")
        return {"values": values, "weights": weights}
    params = {k: float(_number(t, k, where)) for k in DISTRIBUTIONS[name]}
    if "std" in params and params["std"] <= 0:
        raise ConfigError(f"{where}.std: expected > 0, got {params['std']}")
    if "low" in params and params["low"] >= params["high"]:
        raise ConfigError(f"{where}: expected low < high, got low {params['low']}, high {params['high']}")
    return params


def _axis(t: Any, where: str) -> Axis:
    _check_keys(t, _AXIS_KEYS, where)
    if "path" not in t or not isinstance(t["path"], str):
        raise ConfigError(f"{where}.path: missing; expected a scenario key path such as 'plant.road_friction'")
    cross = t.get("cross", False)
    if not isinstance(cross, bool):
        raise ConfigError(f"{where}.cross: expected true/false, got {cross!r}")
    if "distribution" in t:
        return Axis(t["path"], distribution=t["distribution"], cross=cross, **_distribution(t, where))
    has_range = [k for k in ("start", "stop", "step") if k in t]
    if has_range and "values" in t:
        raise ConfigError(f"{where}: expected either values or start/stop/step, got both")
    if has_range:
        if len(has_range) != 3:
            raise ConfigError(f"{where}: a range needs start, stop and step, got only {has_range}")
        return Axis(t["path"], values=_range_values(t, where), cross=cross)
    if "values" not in t:
        raise ConfigError(f"{where}: expected values, start/stop/step or a distribution")
    extra = [k for k in ("low", "high", "mean", "std", "weights") if k in t]
    if extra:
        raise ConfigError(f"{where}: {extra} need a distribution")
    return Axis(t["path"], values=_value_list(t["values"], f"{where}.values"), cross=cross)


def _settings(t: Any) -> dict[str, Any]:
    _check_keys(t, _SWEEP_KEYS, "sweep")
    out: dict[str, Any] = {}
    for key in ("name", "description", "scenario"):
        if key in t and not isinstance(t[key], str):
            raise ConfigError(f"sweep.{key}: expected a string, got {t[key]!r}")
    if "scenario" not in t:
        raise ConfigError("sweep.scenario: missing; expected a scenario file or a bundled scenario name")
    mode = t.get("mode", "grid")
    if mode not in MODES:
        raise ConfigError(f"sweep.mode: expected one of {list(MODES)}, got {mode!r}")
    for key, lo in (("seed", 0), ("samples", 1), ("replicates", 1)):
        if key in t:
            out[key] = _number(t, key, "sweep", integer=True)
            if not lo <= out[key] < 2**63:
                raise ConfigError(f"sweep.{key}: expected an integer >= {lo}, got {out[key]}")
    if "latin_hypercube" in t:
        if not isinstance(t["latin_hypercube"], bool):
            raise ConfigError(f"sweep.latin_hypercube: expected true/false, got {t['latin_hypercube']!r}")
        out["latin_hypercube"] = t["latin_hypercube"]
    out.update(mode=mode, description=t.get("description", ""))
    return out


def _check_mode(spec: SweepSpec) -> None:
    sampled = [a.path for a in spec.axes if a.sampled]
    if spec.mode == "monte_carlo" and (not sampled or not spec.samples):
        raise ConfigError("sweep: monte_carlo expects samples >= 1 and at least one distribution axis")
    if spec.mode != "monte_carlo" and sampled:
        raise ConfigError(f"sweep: distributions need mode = 'monte_carlo'; mode is {spec.mode!r}, "
                          f"distribution axes {sampled}")
    if spec.mode != "monte_carlo" and (spec.samples or spec.latin_hypercube):
        raise ConfigError("sweep: samples and latin_hypercube apply to mode = 'monte_carlo' only")
    paths = [a.path for a in spec.axes]
    dup = sorted({p for p in paths if paths.count(p) > 1})
    if dup:
        raise ConfigError(f"axis: each key path at most once, got {dup} more than once")
    if "scenario.seed" in paths:
        raise ConfigError("axis: scenario.seed is set per run from sweep.seed; use sweep.replicates for repeats")


def sweep_from_dict(data: Mapping[str, Any], source: Path) -> SweepSpec:
    """Build and check a :class:`SweepSpec` from parsed TOML (``source``: the file, for relative paths)."""
    _check_keys(data, ("sweep", "axis"), "")
    if "sweep" not in data:
        raise ConfigError("sweep: missing [sweep] table")
    settings = _settings(data["sweep"])
    axes_raw = data.get("axis", [])
    if not isinstance(axes_raw, list) or not axes_raw:
        raise ConfigError("axis: expected at least one [[axis]] table")
    axes = tuple(_axis(t, f"axis[{i}]") for i, t in enumerate(axes_raw))
    spec = SweepSpec(name=data["sweep"].get("name", source.stem), source=source, axes=axes,
                     scenario=_base_scenario(data["sweep"]["scenario"], source), **settings)
    _check_mode(spec)
    return spec


def load_sweep(name_or_path: str | Path) -> SweepSpec:
    """Read a sweep file (or a bundled sweep by name); errors are one-line ConfigErrors naming the file."""
    path = find_sweep(name_or_path)
    return load_toml_file(path, lambda data: sweep_from_dict(data, path.resolve()), "sweep")
