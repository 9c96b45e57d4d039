"""Sweep files (TOML) -> :class:`SweepSpec`, strictly.

A sweep file names a base scenario (or a base fleet scene) and the axes to vary over it::

    [sweep]
    name = "friction_lag_latency"
    scenario = "paper_cyclist"        # a bundled scenario name, or a path relative to this file
    # fleet = "crossing"              # or: a bundled fleet scene name (cosim/fleet/scenes), or a fleet file
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
    path = "plant.initial_speed_mps"  # a fleet's would be vehicle.plant.initial_speed_mps
    also = ["driver.set_speed_mps"]   # further key paths given the same value in each run
    values = [8.333, 11.111]

    [[axis]]
    path = "radar.latency_s"
    distribution = "truncated_normal" # "uniform" (low, high), "normal" (mean, std),
    mean = 0.1                        # "truncated_normal" (mean, std, low, high),
    std = 0.05                        # "choice" (values, optional weights)
    low = 0.0
    high = 0.2

Every key is declared once on :class:`SweepSection` and :class:`AxisTable`
(:func:`ecu.settings.setting`) and read by the one loader
(:func:`ecu.settings.load`): unknown keys and bad values raise a
:class:`~cosim.errors.ConfigError` naming the file and the key
(``axis[2].distribuion``), with the same suggestion as every configuration file.
Whether each axis's path exists in the scenario (or the fleet) is checked by
:mod:`cosim.sweep.plan` against the resolved base (:mod:`cosim.sweep.subject`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Mapping

from ecu.settings import Kind, Range, SettingError, load, load_toml, setting

from ..errors import ConfigError

MODES = ("grid", "monte_carlo", "one_at_a_time")
#: what a sweep may vary, by the [sweep] key naming its base file (cosim.sweep.subjects holds each one's runs)
SUBJECT_KINDS = ("scenario", "fleet")
DISTRIBUTIONS = {  # name -> required parameters (choice also takes optional weights)
    "uniform": ("low", "high"),
    "normal": ("mean", "std"),
    "truncated_normal": ("mean", "std", "low", "high"),
    "choice": ("values",),
}
_MAX_RANGE_POINTS = 100_000
_SEED_RANGE = (0, 2**63 - 1)


def _value_list(values: Any, where: str) -> tuple:
    if not isinstance(values, list) or not values:
        raise SettingError(where, f"expected a non-empty list, got {values!r}")
    kinds = {str if isinstance(v, str) else bool if isinstance(v, bool) else float for v in values}
    if len(kinds) != 1 or any(isinstance(v, (list, dict)) for v in values):
        raise SettingError(where, f"expected values of one kind (numbers, strings or booleans), got {values!r}")
    if len(set(values)) != len(values):
        raise SettingError(where, f"expected distinct values, got {values!r}")
    return tuple(values)


_VALUES = Kind("non-empty list of distinct values of one kind (numbers, strings or booleans)", _value_list, list)


@dataclass(frozen=True)
class SweepSection:
    """``[sweep]``: the base scenario (or fleet) and how its runs are designed."""

    scenario: str | None = setting(None, doc="the base scenario: a bundled scenario name, or a path relative to "
                                             "this file (give scenario or fleet)")
    fleet: str | None = setting(None, doc="the base fleet scene: a bundled fleet scene name (crd fleet --list), "
                                          "or a path relative to this file (give scenario or fleet)")
    name: str = setting("", doc="the sweep's name (default: the file's stem)")
    description: str = setting("", doc="one line for `crd sweep --list`")
    mode: str = setting("grid", allowed=MODES, doc="grid: every combination; monte_carlo: samples of the "
                        "distribution axes (crossed with the list axes); one_at_a_time: each axis alone")
    seed: int = setting(0, allowed=Range(*_SEED_RANGE), doc="the per-run seeds derive from this and each run's key")
    samples: int | None = setting(None, allowed=Range(1, _SEED_RANGE[1]), doc="monte_carlo: number of samples")
    latin_hypercube: bool = setting(False, doc="monte_carlo: stratify the samples (one per 1/N stratum per axis)")
    replicates: int = setting(1, allowed=Range(1, _SEED_RANGE[1]), doc="runs per combination, each with its own seed")


@dataclass(frozen=True)
class AxisTable:
    """``[[axis]]``: one varied key path: ``values``, a range ``start``/``stop``/``step``, or a ``distribution``."""

    path: str = setting(doc="a scenario key path, e.g. plant.road_friction or objects[0].speed_mps (a fleet's: "
                            "vehicles[1].y_m, vehicle.ecu.strategy)")
    also: tuple[str, ...] = setting((), doc="further key paths given the same value in each run (its column is "
                                            "path's), e.g. a start speed and the driver's set speed")
    values: tuple | None = setting(None, kind=_VALUES, doc="the values (with distribution = \"choice\": the choices)")
    start: int | float | None = setting(None, doc="a range: start + k * step, k = 0, 1, ... up to stop (inclusive)")
    stop: int | float | None = setting(None, doc="see start")
    step: int | float | None = setting(None, doc="see start")
    distribution: str | None = setting(None, allowed=tuple(DISTRIBUTIONS),
                                       doc="uniform (low, high), normal (mean, std), truncated_normal (mean, std, "
                                           "low, high) or choice (values, optional weights)")
    low: float | None = setting(None, doc="distribution parameter")
    high: float | None = setting(None, doc="distribution parameter")
    mean: float | None = setting(None, doc="distribution parameter")
    std: float | None = setting(None, allowed=Range(0.0, math.inf, low_open=True), doc="distribution parameter")
    weights: tuple[float, ...] = setting((), allowed=Range(0.0, math.inf), doc="choice: one non-negative weight per value")
    cross: bool = setting(False, doc="one_at_a_time: cross this axis with every run instead of varying it alone")


@dataclass(frozen=True)
class SweepFile:
    """A sweep file: ``[sweep]`` and one or more ``[[axis]]``."""

    sweep: SweepSection = setting(doc="the sweep's settings")
    axis: tuple[AxisTable, ...] = setting((), doc="the axes")


@dataclass(frozen=True)
class Axis:
    """One varied key path: a list of ``values`` (lists and ranges) or a ``distribution``.

    ``cross`` (one_at_a_time mode): cross this axis with every run instead of varying it alone.
    """

    path: str
    values: tuple = ()
    also: tuple[str, ...] = ()
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
    """A whole sweep file; ``base`` is the resolved path of its base file, a ``subject`` (scenario or fleet)."""

    name: str
    base: Path
    source: Path
    axes: tuple[Axis, ...]
    mode: str = "grid"
    seed: int = 0
    samples: int = 0
    latin_hypercube: bool = False
    replicates: int = 1
    description: str = ""
    subject: str = "scenario"

    @property
    def paths(self) -> tuple[str, ...]:
        """Every key path the runs write: each axis's path and its ``also`` paths."""
        return tuple(p for a in self.axes for p in (a.path, *a.also))


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


#: where each subject's bundled base files are (a bare name in [sweep] scenario / fleet; crd fleet --list)
_BUNDLED_BASES = {"scenario": Path(__file__).resolve().parent.parent / "scenarios",
                  "fleet": Path(__file__).resolve().parent.parent / "fleet" / "scenes"}


def _base_file(kind: str, value: str, source: Path) -> Path:
    if value.endswith(".toml") or "/" in value:
        path = Path(value)
        return path if path.is_absolute() else (source.parent / path).resolve()
    bundled = _BUNDLED_BASES[kind] / f"{value}.toml"
    if not bundled.is_file():
        names = ", ".join(p.stem for p in sorted(_BUNDLED_BASES[kind].glob("*.toml")))
        raise SettingError(f"sweep.{kind}", f"expected a {kind} file or a bundled {kind} name ({names}), got {value!r}")
    return bundled


def _subject(s: SweepSection) -> tuple[str, str]:
    """Which base the sweep names: (kind, value); exactly one of [sweep] scenario and fleet."""
    given = [(k, getattr(s, k)) for k in SUBJECT_KINDS if getattr(s, k) is not None]
    if len(given) != 1:
        raise SettingError("sweep", f"expected one base, scenario or fleet; got {[k for k, _ in given] or 'neither'}")
    return given[0]


def _range_values(t: AxisTable, where: str) -> tuple:
    start, stop, step = t.start, t.stop, t.step
    if step <= 0 or stop < start:
        raise SettingError(where, f"expected step > 0 and stop >= start, got start {start}, stop {stop}, step {step}")
    count = int(math.floor((stop - start) / step + 1e-9)) + 1
    if count > _MAX_RANGE_POINTS:
        raise SettingError(where, f"expected at most {_MAX_RANGE_POINTS} points, got {count}")
    ints = all(isinstance(v, int) for v in (start, stop, step))
    # start + k*step from an integer counter, rounded so 0.1 steps read back as 0.3, not 0.30000000000000004
    return tuple(start + k * step if ints else round(start + k * step, 12) for k in range(count))


_DISTRIBUTION_KEYS = ("low", "high", "mean", "std", "weights", "start", "stop", "step", "values")


def _distribution(t: AxisTable, where: str) -> dict[str, Any]:
    name = t.distribution
    given = [k for k in _DISTRIBUTION_KEYS if getattr(t, k) not in (None, ())]
    missing = [k for k in DISTRIBUTIONS[name] if k not in given]
    extra = [k for k in given if k not in DISTRIBUTIONS[name] and not (name == "choice" and k == "weights")]
    if missing or extra:
        raise SettingError(where, f"distribution {name!r} takes {list(DISTRIBUTIONS[name])}"
                                  f"{' (+ weights)' if name == 'choice' else ''}; missing {missing}, unexpected {extra}")
    if name == "choice":
        if t.weights and (len(t.weights) != len(t.values) or sum(t.weights) <= 0):
            raise SettingError(f"{where}.weights", f"expected {len(t.values)} non-negative weights with a positive "
                                                   f"sum, got {list(t.weights)}")
        return {"values": t.values, "weights": t.weights}
    params = {k: getattr(t, k) for k in DISTRIBUTIONS[name]}
    if "low" in params and params["low"] >= params["high"]:
        raise SettingError(where, f"expected low < high, got low {params['low']}, high {params['high']}")
    return params


def _axis(t: AxisTable, where: str) -> Axis:
    if t.distribution is not None:
        return Axis(t.path, distribution=t.distribution, also=t.also, cross=t.cross, **_distribution(t, where))
    has_range = [k for k in ("start", "stop", "step") if getattr(t, k) is not None]
    if has_range and t.values is not None:
        raise SettingError(where, "expected either values or start/stop/step, got both")
    if has_range:
        if len(has_range) != 3:
            raise SettingError(where, f"a range needs start, stop and step, got only {has_range}")
        return Axis(t.path, values=_range_values(t, where), also=t.also, cross=t.cross)
    if t.values is None:
        raise SettingError(where, "expected values, start/stop/step or a distribution")
    extra = [k for k in ("low", "high", "mean", "std", "weights") if getattr(t, k) not in (None, ())]
    if extra:
        raise SettingError(where, f"{extra} need a distribution")
    return Axis(t.path, values=t.values, also=t.also, cross=t.cross)


def _check_mode(spec: SweepSpec) -> None:
    sampled = [a.path for a in spec.axes if a.sampled]
    if spec.mode == "monte_carlo" and (not sampled or not spec.samples):
        raise SettingError("sweep", "monte_carlo expects samples >= 1 and at least one distribution axis")
    if spec.mode != "monte_carlo" and sampled:
        raise SettingError("sweep", f"distributions need mode = 'monte_carlo'; mode is {spec.mode!r}, "
                                    f"distribution axes {sampled}")
    if spec.mode != "monte_carlo" and (spec.samples or spec.latin_hypercube):
        raise SettingError("sweep", "samples and latin_hypercube apply to mode = 'monte_carlo' only")
    paths = list(spec.paths)
    dup = sorted({p for p in paths if paths.count(p) > 1})
    if dup:
        raise SettingError("axis", f"expected each key path at most once, got {dup} more than once")
    if spec.subject == "scenario" and "scenario.seed" in paths:
        raise SettingError("axis", "scenario.seed is set per run from sweep.seed; use sweep.replicates for repeats")


def sweep_from_dict(data: Mapping[str, Any], source: Path) -> SweepSpec:
    """Build and check a :class:`SweepSpec` from parsed TOML (``source``: the file, for relative paths)."""
    file = load(SweepFile, data)
    if not file.axis:
        raise SettingError("axis", "missing; expected at least one [[axis]] table")
    axes = tuple(_axis(t, f"axis[{i}]") for i, t in enumerate(file.axis))
    s = file.sweep
    kind, value = _subject(s)
    spec = SweepSpec(name=s.name or source.stem, source=source, axes=axes, subject=kind,
                     base=_base_file(kind, value, source), mode=s.mode, seed=s.seed, samples=s.samples or 0,
                     latin_hypercube=s.latin_hypercube, replicates=s.replicates, description=s.description)
    _check_mode(spec)
    return spec


def load_sweep(name_or_path: str | Path) -> SweepSpec:
    """Read a sweep file (or a bundled sweep by name); errors are one-line ConfigErrors naming the file."""
    path = find_sweep(name_or_path)
    return load_toml(path, lambda data: sweep_from_dict(data, path.resolve()), "sweep")
