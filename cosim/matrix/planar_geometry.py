"""What the planar catalogue scenes share: the cell they build from, the standard road, lane centre lines,
parked boxes and the scenario frame every planar cell has."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

import numpy as np

from ..world.reference_line import PlanView

KMH = 3.6
#: lane width (m): Euro NCAP FC v1.1 §2.1.1 (main approach 3.5 m), UN R152's and the bundled scenarios'
LANE_M = 3.5
#: where every scene's road starts (m), behind the ego's start
ROAD_START_M = -30.0
GVT = "GVT"


def straight_road(end_x_m: float, right: tuple[float, ...] = (LANE_M,), left: tuple[float, ...] = (LANE_M,)) -> dict:
    """A straight road from :data:`ROAD_START_M` to ``end_x_m`` with lane -1's centre on y = 0."""
    return {"x_m": ROAD_START_M, "y_m": right[0] / 2.0,
            "geometry": [{"kind": "line", "length_m": max(end_x_m, 10.0) - ROAD_START_M}],
            "lane_sections": [{"left_m": list(left), "right_m": list(right)}]}


def lane_centre(plan: PlanView, t_m: float, s0_m: float, s1_m: float, step_m: float = 1.0) -> np.ndarray:
    """The line at offset ``t_m`` from ``plan`` between stations ``s0_m`` and ``s1_m``, shape (k, 2)."""
    s = np.append(np.arange(s0_m, s1_m, step_m), s1_m)
    x, y, h = plan.pose(s)
    return np.column_stack([x - t_m * np.sin(h), y + t_m * np.cos(h)])


@dataclass(frozen=True)
class SceneCell:
    """What a scene builder gets: the cell's values, its layout and target, the ego's size, the phase shift."""

    cell_id: str
    params: Mapping[str, Any]
    layout: Mapping[str, Any]
    target: Mapping[str, Any]
    ego_width_m: float
    ego_length_m: float
    shift_s: float

    @property
    def v(self) -> float:
        return self.params["ego_speed_kmh"] / KMH

    @property
    def vt(self) -> float:
        return self.params.get("target_speed_kmh", 0.0) / KMH

    @property
    def x0(self) -> float:
        """Where the scene's x = 0 lies: the phase shift at the ego's speed."""
        return self.v * self.shift_s

    @property
    def t_start(self) -> float:
        """When the protocol's test starts at phase 0: the steady approach (``settle_s``)."""
        return float(self.params.get("settle_s", 2.0))

    def target_object(self, name: str | None = None, **placement: Any) -> dict[str, Any]:
        obj = {"name": name or self.cell_id, "length_m": self.target["length_m"], "width_m": self.target["width_m"]}
        if self.target.get("target_class"):
            obj["target_class"] = self.target["target_class"]
        obj.update(placement)
        return obj


def car(name: str, **placement: Any) -> dict[str, Any]:
    return {"name": name, "target_class": GVT, **placement}


def parked_objects(cell: SceneCell, x_ref: float) -> list[dict[str, Any]]:
    """The layout's parked boxes (obstruction vehicles), placed from the synchronisation point ``x_ref``."""
    return [{"name": f"parked {i + 1}", "target_class": GVT, "length_m": row[2], "width_m": row[3],
             "pose": {"x_m": x_ref + row[0], "y_m": row[1], "heading_rad": 0.0}}
            for i, row in enumerate(cell.layout["parked"])]


def impact_y(cell: SceneCell) -> float:
    """The impact location on the ego's front (m, left positive; Euro NCAP FC v1.1 §1.2.5)."""
    return (cell.layout["impact_pct"] / 100.0 - 0.5) * cell.ego_width_m


def crossing_time_s(distance_m: float, accel_m: float, speed_mps: float) -> float:
    """Time to cover ``distance_m`` from rest: constant acceleration over ``accel_m`` (mean speed v/2), then v."""
    return 2.0 * accel_m / speed_mps + (distance_m - accel_m) / speed_mps


def frame(cell: SceneCell, duration_s: float, road: dict, objects: list, **extra: Any) -> dict[str, Any]:
    """The scenario mapping every planar cell shares: the robot driver, the road, the objects, the end."""
    steering = extra.pop("steering", {"model": "path_following", "lane": -1})
    release = cell.params.get("driver_release", True)
    data = {
        "scenario": {"name": cell.cell_id, "duration_s": round(float(duration_s) + cell.shift_s, 3)},
        "plant": {"initial_speed_mps": cell.v, "road_friction": float(cell.params.get("road_friction", 1.0))},
        "driver": {"model": "hold_speed", "set_speed_mps": cell.v, "release_drop_mps": 5.0 / KMH if release else 0.0,
                   "steering": steering},
        "road": road, "objects": objects,
    }
    end = extra.pop("end", "standstill")
    if end != "time":
        data["end"] = {end: True}
    data.update(extra)
    return data
