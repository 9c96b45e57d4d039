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

import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Any, Mapping

from ..errors import ConfigError
from ..scenarios.config import OBJECT_TRACK_PERIOD_S
from ..scenarios.loader import load_toml_file

KMH = 3.6
SCORINGS = ("r152", "ncap", "false_positive", "follow")
_SERIES_KEYS = {
    "group", "ego_speed_kmh", "target", "target_speed_kmh", "lateral_m", "gap_m", "headway_s",
    "start_ttc_s", "settle_s", "brake_decel_mps2", "brake_ramp_s", "brake_to_speed_kmh", "brake_at_s",
    "lateral_end_m", "lateral_speed_mps", "lateral_at_gap_m", "road_friction", "max_impact_kmh",
    "require_no_contact", "extended", "duration_s", "end", "driver_release", "source", "note",
}
_BOOL_KEYS = {"require_no_contact", "extended", "driver_release"}
_STR_KEYS = {"group", "target", "end", "source", "note"}
_TOP_KEYS = {"catalogue", "sources", "targets", "scenario", "scoring", "series"}
_ENDS = ("standstill", "matched_speed", "time")


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

    def get(self, key: str, default: Any = None) -> Any:
        return self.params.get(key, default)

    def scenario_dict(self, phase: int = 0, phases: int = 1) -> dict[str, Any]:
        """The cell as a scenario mapping (plain data, picklable) at radar phase ``phase`` of ``phases``."""
        p = self.params
        v, vt = p["ego_speed_kmh"] / KMH, p.get("target_speed_kmh", 0.0) / KMH
        settle, shift_s = p.get("settle_s", 2.0), OBJECT_TRACK_PERIOD_S * phase / phases
        closing = max(0.0, v - vt)
        gap = _start_gap(p, v, closing, settle) + closing * shift_s
        obj = {"name": self.cell_id, "position_m": gap, "speed_mps": vt, "length_m": self.target["length_m"],
               "width_m": self.target["width_m"], "lateral_m": float(p.get("lateral_m", 0.0))}
        obj.update(_object_motion(p, settle + shift_s))
        data = _deep_merge(self.base, {
            "scenario": {"name": self.cell_id, "duration_s": _duration(p, v, vt, gap, settle)},
            "plant": {"initial_speed_mps": v, "road_friction": float(p.get("road_friction", 1.0))},
            "driver": {"model": "hold_speed", "set_speed_mps": v,
                       "release_drop_mps": 5.0 / KMH if p.get("driver_release", True) else 0.0},
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
        raise ConfigError("series: expected gap_m or headway_s for a cell without closing speed")
    return closing * (settle + float(p.get("start_ttc_s", 4.0)))


def _object_motion(p: Mapping[str, Any], t0_s: float) -> dict[str, Any]:
    out: dict[str, Any] = {}
    if p.get("brake_decel_mps2", 0.0) > 0.0:
        out.update(brake_decel_mps2=float(p["brake_decel_mps2"]), brake_ramp_s=float(p.get("brake_ramp_s", 0.0)),
                   brake_to_speed_mps=p.get("brake_to_speed_kmh", 0.0) / KMH,
                   brake_at_s=t0_s + float(p.get("brake_at_s", 0.0)))
    if "lateral_end_m" in p:
        out.update(lateral_end_m=float(p["lateral_end_m"]), lateral_speed_mps=float(p["lateral_speed_mps"]),
                   lateral_at_gap_m=float(p["lateral_at_gap_m"]))
    return out


def _duration(p: Mapping[str, Any], v: float, vt: float, gap: float, settle: float) -> float:
    """Long enough to reach the target and stop: time to close the gap, plus a stop, plus 3 s."""
    if "duration_s" in p:
        return float(p["duration_s"])
    closing = max(v - vt, 0.5)
    brake_s = v / max(p.get("brake_decel_mps2", 0.0), 1e-9) if p.get("brake_decel_mps2") else 0.0
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
    return load_toml_file(path, lambda data: _build(data, path), "catalogue")


def _need(table: Mapping[str, Any], key: str, where: str, kind: type | tuple) -> Any:
    """``table[key]``, which must exist and be of ``kind`` (a bool is not a number here)."""
    path = f"{where}.{key}" if where else key
    if not isinstance(table, Mapping) or key not in table:
        raise ConfigError(f"{path}: missing")
    value = table[key]
    if not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool):
        raise ConfigError(f"{path}: expected {getattr(kind, '__name__', kind)}, got {value!r}")
    return value


def _check_source(table: Mapping[str, Any], sources: Mapping[str, str], where: str) -> None:
    src = _need(table, "source", where, str)
    for key in src.split("+"):
        if key.strip() not in sources:
            raise ConfigError(f"{where}.source: unknown source {key!r}; expected one of {sorted(sources)}")


def _build(data: Mapping[str, Any], path: Path) -> Catalogue:
    for key in data:
        if key not in _TOP_KEYS:
            raise ConfigError(f"unknown key {key!r}; expected one of {sorted(_TOP_KEYS)}")
    head = _need(data, "catalogue", "", dict)
    scoring = _need(head, "scoring", "catalogue", str)
    if scoring not in SCORINGS:
        raise ConfigError(f"catalogue.scoring: expected one of {list(SCORINGS)}, got {scoring!r}")
    sources = {k: str(v) for k, v in _need(data, "sources", "", dict).items()}
    targets = _need(data, "targets", "", dict)
    for name, t in targets.items():
        _check_source(t, sources, f"targets.{name}")
        for key in ("length_m", "width_m"):
            _need(t, key, f"targets.{name}", (int, float))
    table = data.get("scoring", {})
    if table:
        _check_source(table, sources, "scoring")
    name = path.stem
    cells = tuple(c for i, s in enumerate(_need(data, "series", "", list))
                  for c in _series(s, i, name, targets, sources, data.get("scenario", {})))
    ids = [c.cell_id for c in cells]
    if len(set(ids)) != len(ids):
        raise ConfigError(f"series: duplicate cell ids {sorted({i for i in ids if ids.count(i) > 1})}")
    return Catalogue(name, str(head.get("title", name)), scoring, str(path), sources, table, cells)


def _series(s: Mapping[str, Any], i: int, cat: str, targets: Mapping, sources: Mapping,
            base: Mapping[str, Any]) -> list[Cell]:
    where = f"series[{i}]"
    for key in s:
        if key not in _SERIES_KEYS:
            raise ConfigError(f"{where}.{key}: unknown key; expected one of {sorted(_SERIES_KEYS)}")
    _check_source(s, sources, where)
    group = _need(s, "group", where, str)
    speeds = _need(s, "ego_speed_kmh", where, list)
    target = targets.get(_need(s, "target", where, str))
    if target is None:
        raise ConfigError(f"{where}.target: unknown target {s['target']!r}; expected one of {sorted(targets)}")
    if s.get("end", "standstill") not in _ENDS:
        raise ConfigError(f"{where}.end: expected one of {list(_ENDS)}, got {s['end']!r}")
    cells = []
    for j, speed in enumerate(speeds):
        params = {}
        for key, value in s.items():
            if isinstance(value, list):
                if len(value) != len(speeds):
                    raise ConfigError(f"{where}.{key}: expected {len(speeds)} values (one per ego speed),"
                                      f" got {len(value)}")
                value = value[j]
            params[key] = _checked(key, value, f"{where}.{key}")
        cell_id = f"{group}-{speed:g}"
        cells.append(Cell(cat, cell_id, group, params, dict(target), base))
    return cells


def _checked(key: str, value: Any, where: str) -> Any:
    """A cell value of the right type: true/false, a string, or a finite number (>= 0 except lateral_m)."""
    if key in _BOOL_KEYS:
        ok, expected = isinstance(value, bool), "true or false"
    elif key in _STR_KEYS:
        ok, expected = isinstance(value, str), "a string"
    else:
        number = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        ok = number and (value >= 0.0 or key == "lateral_m")
        expected = "a finite number" + ("" if key == "lateral_m" else " >= 0")
    if not ok:
        raise ConfigError(f"{where}: expected {expected}, got {value!r}")
    return value

