"""The ``[series.layout]`` table of a planar catalogue series: the scene's geometry, declared once per key.

A series with ``scene = "<kind>"`` (:data:`cosim.matrix.planar_scenes.SCENES`) gives the geometry of
its cells here; a number key may be a list, one value per ego speed of the series, like the series'
own keys. Every scene reads the keys it needs and refuses a table that lacks one
(:func:`check_layout`); the others keep their defaults. Frame and conventions:
:mod:`cosim.matrix.planar_scenes`.
"""

from __future__ import annotations

import dataclasses
import typing
from dataclasses import dataclass
from typing import Any, Mapping

from ecu.settings import Range, SettingError, keys, load, setting

_M = Range(-1e4, 1e4)
_POSITIVE = Range(0.0, 1e4, low_open=True)
SIDES = ("near", "far")
ADJACENT = ("free", "occupied")
TURNS = ("left", "right")


@dataclass(frozen=True)
class Layout:
    """The geometry of one planar cell (each scene names the keys it reads)."""

    impact_pct: float = setting(50.0, unit="%", allowed=Range(-50.0, 150.0),
                                doc="where the target's reference point meets the ego's front: % of its width, "
                                    "0 = right edge, 100 = left edge (Euro NCAP FC v1.1 §1.2.5)")
    side: str = setting("near", allowed=SIDES, doc="the target comes from the near (right) or far (left) side")
    start_distance_m: float = setting(4.0, unit="m", allowed=_POSITIVE,
                                      doc="crossing: the target's reference point starts this far from the ego's "
                                          "path (the 50 % impact point)")
    accel_distance_m: float = setting(1.0, unit="m", allowed=_POSITIVE,
                                      doc="crossing: the target reaches its speed after this distance from rest")
    reference_m: float = setting(0.0, unit="m", allowed=Range(-5.0, 5.0),
                                 doc="the target's reference point ahead of its box's centre along its heading")
    parked: tuple[tuple[float, ...], ...] = setting((), unit="m", allowed=_M,
                                                    doc="parked boxes [dx_m, y_m, length_m, width_m]: centre x "
                                                        "from the synchronisation point, centre y, size")
    turn_radius_m: float = setting(10.0, unit="m", allowed=_POSITIVE, doc="turn_across: the ego's arc radius")
    clothoid_deg: float = setting(20.0, unit="deg", allowed=Range(0.0, 90.0),
                                  doc="turn_across: heading change of each clothoid (1500 m to the arc radius)")
    arc_deg: float = setting(50.0, unit="deg", allowed=Range(0.0, 180.0), doc="turn_across: heading change of the arc")
    vut_distance_m: float = setting(10.0, unit="m", allowed=_POSITIVE,
                                    doc="turn_across: the ego's front this far before the collision point (along x) "
                                        "when the target's front is target_distance_m from it")
    target_distance_m: float = setting(30.0, unit="m", allowed=_POSITIVE, doc="turn_across: see vut_distance_m")
    curve_radius_m: float = setting(100.0, unit="m", allowed=_POSITIVE, doc="curves: the reference line's radius")
    curve_turn: str = setting("left", allowed=TURNS, doc="curves: the direction the road bends")
    curve_angle_deg: float = setting(90.0, unit="deg", allowed=Range(1.0, 180.0), doc="curves: the arc's angle")
    curve_station_m: float = setting(50.0, unit="m", allowed=Range(0.0, 1e4),
                                     doc="curves: where along the arc the encounter is (from the arc's start)")
    lateral_m: float = setting(0.0, unit="m", allowed=Range(-20.0, 20.0),
                               doc="the target's centre across the ego's path (left positive)")
    gap_m: float = setting(30.0, unit="m", allowed=Range(-1e3, 1e4),
                           doc="the target's rear ahead of the ego's front at t = 0 (negative: behind)")
    headway_s: float = setting(1.0, unit="s", allowed=Range(0.0, 100.0), doc="a lead car's headway at the ego's speed")
    reveal_ttc_s: float = setting(1.5, unit="s", allowed=_POSITIVE,
                                  doc="the ego's time to the hidden target when it is uncovered")
    lateral_speed_mps: float = setting(2.0, unit="m/s", allowed=_POSITIVE, doc="a lane change's lateral speed")
    adjacent: str = setting("free", allowed=ADJACENT,
                            doc="the lane left of the ego: free, or occupied by a queue at the ego's speed")
    stop_y_m: float = setting(-2.05, unit="m", allowed=Range(-20.0, 20.0),
                              doc="kerb_stop: where the pedestrian's box centre stops")
    decel_mps2: float = setting(2.0, unit="m/s^2", allowed=Range(0.1, 15.0), doc="a lead car's deceleration")
    turn_speed_kmh: float = setting(20.0, unit="km/h", allowed=Range(1.0, 200.0), doc="a lead car's turning speed")

    def __post_init__(self) -> None:
        for i, row in enumerate(self.parked):
            if len(row) != 4:
                raise SettingError(f"parked[{i}]", f"expected [dx_m, y_m, length_m, width_m], got {list(row)}")


_LAYOUT_KEYS = keys(Layout)


def _per_cell(name: str) -> bool:
    """Whether a list value of ``name`` gives one value per cell (a scalar key), not the value itself."""
    hint = _LAYOUT_KEYS[name].hint
    return typing.get_origin(hint) is not tuple


def check_layout(table: Any, n: int, required: tuple[str, ...], where: str) -> list[dict[str, Any]]:
    """The layout of each of the series' ``n`` cells as plain data (checked, defaults filled in)."""
    if not isinstance(table, Mapping):
        raise SettingError(where, f"expected a table, got {table!r}")
    for name in required:
        if name not in table:
            raise SettingError(f"{where}.{name}", "missing; this scene needs it")
    cells = []
    for j in range(n):
        row = {}
        for name, value in table.items():
            if isinstance(value, list) and name in _LAYOUT_KEYS and _per_cell(name):
                if len(value) != n:
                    raise SettingError(f"{where}.{name}", f"expected {n} values (one per ego speed), got {len(value)}")
                value = value[j]
            row[name] = value
        cells.append(dataclasses.asdict(load(Layout, row, where)))
    return cells
