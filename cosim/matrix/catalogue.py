"""Test catalogues: a protocol's test matrix as data (one TOML file each), expanded into scenarios.

A catalogue names its scoring rule and its sources, and lists ``[[series]]``
of cells; a list value in a series gives one cell per entry (all lists of a
series have the length of ``ego_speed_kmh``), a scalar applies to every cell.
Every series, target and scoring table cites a key of ``[sources]`` (the
protocol document, its version and clause). The format knows nothing of how
cells are run: :meth:`Cell.scenario_dict` gives a plain scenario mapping for
:func:`cosim.scenarios.loader.scenario_from_dict`, for any runner.

Scenario of a cell (times from t = 0, when the ego is at its test speed):

* the ego starts at ``ego_speed_kmh`` (``[plant] initial_speed_mps``) and the
  robot driver holds it (PI, never brakes; releases the accelerator once the
  speed has dropped 5 km/h unless ``driver_release = false``);
* the target's rear starts ``gap_m``, ``headway_s * v_ego`` or
  ``closing_speed * (settle_s + start_ttc_s)`` ahead: the protocol's TTC at the
  start of the test after ``settle_s`` of steady approach (R152: a straight
  approach of at least 2 s);
* ``brake_at_s`` counts from the end of the settling time;
* phase ``i`` of ``N`` shifts the encounter by ``i/N`` of one 50 ms radar
  update: the start gap grows by ``closing * 0.05 * i/N`` and time triggers
  move by ``0.05 * i/N`` s;
* the run ends on contact, at standstill (stationary target), at matched speed
  (moving target: Euro NCAP's end of a longitudinal test) or at ``duration_s``.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Mapping

from ecu.settings import Kind, Range, SettingError, keys, load, load_toml, setting, type_text, unknown_key, value_of

from ..errors import ConfigError
from ..scenarios.config import OBJECT_TRACK_PERIOD_S
from ..scenarios.loader import scenario_from_dict
from ..world.targets import TARGET_CLASSES
from . import planar_scenes, xosc_cells
from .planar_layout import check_layout
from .planar_scenes import SCENES
from .scorings import SCORINGS, scoring_named

KMH = 3.6
ENDS = ("standstill", "matched_speed", "time")


@dataclass(frozen=True)
class CellKeys:
    """The keys of a ``[[series]]`` table, as each cell sees them (unset: not given).

    A list value gives one cell per entry (every list of a series has the length
    of ``ego_speed_kmh``, which is always a list); a scalar applies to every cell.
    """

    group: str = setting(doc="the cells' group; a cell's id is <group>-<ego speed>")
    ego_speed_kmh: float = setting(unit="km/h", allowed=Range(0.0, 300.0), doc="the ego's test speed (a list: one cell each)")
    target: str = setting(doc="a name of [targets]")
    source: str = setting(doc="the key(s) of [sources] the series cites, joined by +")
    target_speed_kmh: float = setting(0.0, unit="km/h", allowed=Range(0.0, 300.0), doc="the target's speed")
    lateral_m: float = setting(0.0, unit="m", allowed=Range(-20.0, 20.0),
                               doc="the target's centre offset across the path, left positive")
    gap_m: float | None = setting(None, unit="m", allowed=Range(0.0, 1e4), doc="start gap (the target's rear ahead of "
                                  "the ego's front bumper); else headway_s, else from start_ttc_s")
    headway_s: float | None = setting(None, unit="s", allowed=Range(0.0, 100.0), doc="start gap = headway_s * ego speed")
    start_ttc_s: float = setting(4.0, unit="s", allowed=Range(0.0, 100.0), doc="TTC at the start of the test, after settle_s")
    settle_s: float = setting(2.0, unit="s", allowed=Range(0.0, 100.0),
                              doc="steady approach before the test starts (R152: at least 2 s)")
    brake_decel_mps2: float = setting(0.0, unit="m/s^2", allowed=Range(0.0, 15.0), doc="the target brakes (0: never)")
    brake_ramp_s: float = setting(0.0, unit="s", allowed=Range(0.0, 10.0), doc="... reaching it within this")
    brake_to_speed_kmh: float = setting(0.0, unit="km/h", allowed=Range(0.0, 300.0), doc="... down to this")
    brake_at_s: float = setting(0.0, unit="s", allowed=Range(0.0, 3600.0), doc="... starting this long after settle_s")
    lateral_end_m: float | None = setting(None, unit="m", allowed=Range(-20.0, 20.0), doc="the target moves across to this")
    lateral_speed_mps: float | None = setting(None, unit="m/s", allowed=Range(0.0, 10.0), doc="... at this speed")
    lateral_at_gap_m: float | None = setting(None, unit="m", allowed=Range(0.0, 1e4), doc="... once the gap falls to this")
    road_friction: float = setting(1.0, allowed=Range(0.0, 1.5), doc="road friction coefficient")
    max_impact_kmh: float | None = setting(None, unit="km/h", allowed=Range(0.0, 300.0),
                                           doc="r152: the highest allowed relative impact speed (0: no contact)")
    require_no_contact: bool | None = setting(None, doc="ncap: the cell must be green")
    extended: bool | None = setting(None, doc="ncap: an extended-range cell (scores 1.0 unless red)")
    duration_s: float | None = setting(None, unit="s", allowed=Range(0.0, 3600.0, low_open=True),
                                       doc="default: time to close the gap, stop, plus 3 s")
    end: str | None = setting(None, allowed=ENDS, doc="how the run ends (default: standstill for a standing "
                              "target, matched_speed for a moving one)")
    driver_release: bool = setting(True, doc="the robot releases the accelerator after a 5 km/h drop")
    note: str | None = setting(None, doc="free text")
    xosc: str | None = setting(None, doc="an OpenSCENARIO file that gives the cell's whole scenario, relative to "
                                        "the catalogue (cosim.matrix.xosc_cells); the other keys feed the scoring")
    ego: str | None = setting(None, doc="xosc: the entity that is the equipped car (default Ego/hero)")
    scene: str | None = setting(None, allowed=tuple(SCENES), doc="a planar scene (cosim.matrix.planar_scenes) "
                                "builds the cell's road, objects and paths; its geometry is in layout")
    layout: Mapping[str, Any] | None = setting(None, kind=Kind("table (cosim.matrix.planar_layout.Layout)",
                                                               lambda value, where: value),
                                               doc="scene: the geometry of its cells (a number key may be a "
                                                   "list, one value per ego speed)")


_CELL_KEYS = keys(CellKeys)
#: a cell's value of a key it does not give (keys without one: the cell's scenario depends on their presence)
_CELL_DEFAULTS = {k.name: k.default for k in _CELL_KEYS.values() if not k.required and k.default is not None}
_SCALAR_ONLY = ("group", "target", "source", "layout")


def _partial_scenario(value: Any, where: str) -> Mapping[str, Any]:
    """A partial scenario mapping, checked by the scenario loader, kept as data for the cells.

    ``[scenario.driver.steering]`` is checked with each series' first cell (:func:`_check_first_cell`), not
    here: alone it lacks the lane and the road that the cells add (e.g. a third-party plant's geometry for
    the path-following driver, which the planar cells need)."""
    alone = value
    if isinstance(value, Mapping) and isinstance(value.get("driver"), Mapping) and "steering" in value["driver"]:
        alone = {**value, "driver": {k: v for k, v in value["driver"].items() if k != "steering"}}
    try:
        scenario_from_dict(alone)
    except SettingError as exc:
        raise exc.under(where) from None
    return value


def _check_first_cell(cells: list[Cell], where: str) -> None:
    """The series' first cell as it will run (``[scenario]`` merged in), checked by the scenario loader."""
    if cells:
        try:
            scenario_from_dict(cells[0].scenario_dict())
        except SettingError as exc:
            raise SettingError(exc.under("scenario").path,
                               f"{exc.problem} (checked in {where}'s first cell, {cells[0].cell_id})") from None


@dataclass(frozen=True)
class CatalogueHead:
    """``[catalogue]``: what the catalogue is and how it is scored."""

    scoring: str = setting(allowed=tuple(SCORINGS), doc="the protocol's scoring (cosim.matrix.scorings)")
    title: str = setting("", doc="the report's heading (default: the file's stem)")


@dataclass(frozen=True)
class Target:
    """``[targets.<name>]``: a target's body."""

    length_m: float = setting(unit="m", allowed=Range(0.0, 50.0, low_open=True), doc="length along the path")
    width_m: float = setting(unit="m", allowed=Range(0.0, 10.0, low_open=True), doc="width across the path")
    source: str = setting(doc="the key(s) of [sources] the dimensions cite, joined by +")
    target_class: str | None = setting(None, allowed=tuple(TARGET_CLASSES),
                                       doc="planar cells: the world's target class (its radar size class)")


@dataclass(frozen=True)
class CatalogueFile:
    """A catalogue file: every table but ``[[series]]``'s cells, which :func:`_series` reads."""

    catalogue: CatalogueHead = setting(doc="title and scoring")
    sources: Mapping[str, str] = setting(doc="source key = the document, its version and clause")
    targets: Mapping[str, Target] = setting(doc="the targets by name")
    series: tuple[Mapping[str, Any], ...] = setting(doc="the cells (see CellKeys)")
    scenario: Mapping[str, Any] = setting(factory=dict, doc="a partial scenario every cell starts from",
                                          kind=Kind("partial scenario (scenario file tables)", _partial_scenario))
    scoring: Mapping[str, Any] = setting(factory=dict, doc="the scoring's own table (its declared keys)")


@dataclass(frozen=True)
class Cell:
    """One test of a catalogue: its parameters (``params``, after broadcasting) and identity."""

    catalogue: str
    cell_id: str
    group: str
    params: Mapping[str, Any]
    target: Mapping[str, Any]
    base: Mapping[str, Any]

    @property
    def ego_speed_kmh(self) -> float:
        return float(self.params["ego_speed_kmh"])

    def get(self, key: str) -> Any:
        """The cell's value of ``key``: given, else its declared default (``None``: not given, no default)."""
        return self.params.get(key, _CELL_DEFAULTS.get(key))

    def scenario_dict(self, phase: int = 0, phases: int = 1) -> dict[str, Any]:
        """The cell as a scenario mapping (plain data, picklable) at radar phase ``phase`` of ``phases``."""
        if self.params.get("xosc") is not None:
            return xosc_cells.scenario_dict(self.params, self.base, _deep_merge, phase, phases)
        if self.params.get("scene") is not None:
            return planar_scenes.scenario_dict(self.cell_id, {**_CELL_DEFAULTS, **self.params}, self.target, self.base,
                                               _deep_merge, phase, phases)
        p = {**_CELL_DEFAULTS, **self.params}
        v, vt = p["ego_speed_kmh"] / KMH, p["target_speed_kmh"] / KMH
        settle, shift_s = p["settle_s"], OBJECT_TRACK_PERIOD_S * phase / phases
        closing = max(0.0, v - vt)
        gap = _start_gap(p, v, closing, settle) + closing * shift_s
        obj = {"name": self.cell_id, "position_m": gap, "speed_mps": vt, "length_m": self.target["length_m"],
               "width_m": self.target["width_m"], "lateral_m": float(p["lateral_m"])}
        obj.update(_object_motion(p, settle + shift_s))
        data = _deep_merge(self.base, {
            "scenario": {"name": self.cell_id, "duration_s": _duration(p, v, vt, gap, settle)},
            "plant": {"initial_speed_mps": v, "road_friction": float(p["road_friction"])},
            "driver": {"model": "hold_speed", "set_speed_mps": v,
                       "release_drop_mps": 5.0 / KMH if p["driver_release"] else 0.0},
            "objects": [obj],
        })
        end = p.get("end") or ("matched_speed" if vt > 0.0 else "standstill")
        if end != "time":
            data.setdefault("end", {})[end] = True
        return data


def _start_gap(p: Mapping[str, Any], v: float, closing: float, settle: float) -> float:
    if "gap_m" in p:
        return float(p["gap_m"])
    if "headway_s" in p:
        return float(p["headway_s"]) * v
    if closing <= 0.0:
        raise SettingError("series", "expected gap_m or headway_s for a cell without closing speed")
    return closing * (settle + float(p["start_ttc_s"]))


def _object_motion(p: Mapping[str, Any], t0_s: float) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if p["brake_decel_mps2"] > 0.0:
        out.update(brake_decel_mps2=float(p["brake_decel_mps2"]), brake_ramp_s=float(p["brake_ramp_s"]),
                   brake_to_speed_mps=p["brake_to_speed_kmh"] / KMH, brake_at_s=t0_s + float(p["brake_at_s"]))
    if "lateral_end_m" in p:
        out.update(lateral_end_m=float(p["lateral_end_m"]), lateral_speed_mps=float(p["lateral_speed_mps"]),
                   lateral_at_gap_m=float(p["lateral_at_gap_m"]))
    return out


def _duration(p: Mapping[str, Any], v: float, vt: float, gap: float, settle: float) -> float:
    """Long enough to reach the target and stop: time to close the gap, plus a stop, plus 3 s."""
    if "duration_s" in p:
        return float(p["duration_s"])
    closing = max(v - vt, 0.5)
    brake_s = v / max(p["brake_decel_mps2"], 1e-9) if p["brake_decel_mps2"] else 0.0
    return round(settle + gap / closing + brake_s + v / 4.0 + 3.0, 2)


def _deep_merge(a: Mapping[str, Any], b: Mapping[str, Any]) -> dict[str, Any]:
    out = {k: (dict(v) if isinstance(v, Mapping) else v) for k, v in a.items()}
    for k, v in b.items():
        out[k] = _deep_merge(out[k], v) if isinstance(v, Mapping) and isinstance(out.get(k), Mapping) else v
    return out


@dataclass(frozen=True)
class Catalogue:
    """A loaded catalogue: identity, scoring rule and its table, sources, cells."""

    name: str
    title: str
    scoring: str
    path: str
    sources: Mapping[str, str]
    scoring_table: Mapping[str, Any]
    cells: tuple[Cell, ...]


def bundled() -> dict[str, Path]:
    """The catalogues shipped with crd: name -> path."""
    root = resources.files("cosim") / "catalogues"
    return {Path(str(f)).stem: Path(str(f)) for f in root.iterdir() if str(f).endswith(".toml")}


def resolve_path(spec: str) -> Path:
    """A catalogue file path, or the name of a bundled catalogue."""
    path = Path(spec)
    if path.is_file():
        return path
    known = bundled()
    if spec in known:
        return known[spec]
    raise ConfigError(f"{spec}: no such catalogue file; bundled catalogues: {', '.join(sorted(known))}")


def load_catalogue(spec: str | Path) -> Catalogue:
    """Read and check one catalogue; errors name the file and the key."""
    path = resolve_path(str(spec))
    return load_toml(path, lambda data: _build(data, path), "catalogue")


def _check_source(src: str, sources: Mapping[str, str], where: str) -> None:
    for key in src.split("+"):
        if key.strip() not in sources:
            raise SettingError(f"{where}.source", f"unknown source {key!r}; expected one of {sorted(sources)}")


def _build(data: Mapping[str, Any], path: Path) -> Catalogue:
    f = load(CatalogueFile, data)
    scoring = scoring_named(f.catalogue.scoring)
    sources = dict(f.sources)
    for name, target in f.targets.items():
        _check_source(target.source, sources, f"targets.{name}")
    table = load(scoring.table, f.scoring, "scoring")
    if f.scoring:
        _check_source(table.source, sources, "scoring")
    name = path.stem
    cells = tuple(c for i, s in enumerate(f.series)
                  for c in _series(s, f"series[{i}]", (name, scoring.required_keys, path.parent), f.targets, sources,
                                   f.scenario))
    ids = [c.cell_id for c in cells]
    if len(set(ids)) != len(ids):
        raise SettingError("series", f"expected distinct cell ids, got {sorted({i for i in ids if ids.count(i) > 1})} "
                                     "more than once")
    return Catalogue(name, f.catalogue.title or name, scoring.name, str(path), sources, table, cells)


def _series_values(s: Mapping[str, Any], where: str, required: tuple[str, ...]) -> tuple[int, dict[str, Any]]:
    """The number of cells and each key's checked value (a list: one per cell)."""
    for key in s:
        if key not in _CELL_KEYS:
            raise unknown_key(where, key, _CELL_KEYS)
    needed = ("group", "ego_speed_kmh", "target", "source") + required
    if "lateral_end_m" in s:  # a lateral motion needs its speed and its trigger
        needed += ("lateral_speed_mps", "lateral_at_gap_m")
    for key in needed:
        if key not in s:
            raise SettingError(f"{where}.{key}", f"missing; expected {type_text(_CELL_KEYS[key])}")
    speeds = s["ego_speed_kmh"]
    if not isinstance(speeds, list) or not speeds:
        raise SettingError(f"{where}.ego_speed_kmh", f"expected a list of test speeds (one cell each), got {speeds!r}")
    values: dict[str, Any] = {}
    for key, value in s.items():
        here = f"{where}.{key}"
        if isinstance(value, list) and key not in _SCALAR_ONLY:
            if len(value) != len(speeds):
                raise SettingError(here, f"expected {len(speeds)} values (one per ego speed), got {len(value)}")
            values[key] = [value_of(_CELL_KEYS[key], v, f"{here}[{j}]") for j, v in enumerate(value)]
        else:
            values[key] = value_of(_CELL_KEYS[key], value, here)
    return len(speeds), values


def _layouts(values: Mapping[str, Any], n: int, where: str) -> list[dict[str, Any]]:
    """A planar series' per-cell layouts (none without ``scene``; ``layout`` without ``scene``: an error)."""
    if values.get("scene") is None:
        if "layout" in values:
            raise SettingError(f"{where}.layout", "is read only by a planar scene; expected scene = ...")
        return []
    return check_layout(values.get("layout", {}), n, SCENES[values["scene"]][1], f"{where}.layout")


def _series(s: Mapping[str, Any], where: str, cat: tuple[str, tuple[str, ...]], targets: Mapping[str, Target],
            sources: Mapping[str, str], base: Mapping[str, Any]) -> list[Cell]:
    name, required, base_dir = cat
    n, values = _series_values(s, where, required)
    _check_source(values["source"], sources, where)
    target = targets.get(values["target"])
    if target is None:
        raise SettingError(f"{where}.target", f"unknown target {values['target']!r}; expected one of {sorted(targets)}")
    layouts = _layouts(values, n, where)
    cells = []
    for j in range(n):
        params = {key: value[j] if isinstance(value, list) else value for key, value in values.items()}
        if layouts:
            params["layout"] = layouts[j]
        xosc_cells.resolve(params, base_dir)
        cells.append(Cell(name, f"{params['group']}-{params['ego_speed_kmh']:g}", params["group"], params,
                          {"length_m": target.length_m, "width_m": target.width_m, "source": target.source,
                           "target_class": target.target_class}, base))
    if "steering" in base.get("driver", {}):
        _check_first_cell(cells, where)
    return cells
