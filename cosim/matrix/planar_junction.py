"""Planar catalogue scenes with cars: Euro NCAP's junction scenarios and the emergency-steering cells.

See :mod:`cosim.matrix.planar_scenes` for the frame and the phase shift. Approximations (each said
where it is made): the ego's turn is followed by the robot driver's pure pursuit through the
protocol's clothoid-arc-clothoid waypoints, so its front is on the path within the pursuit's error;
targets that the protocol accelerates (CCCscp's GVT) move at their test speed from t = 0; a hidden
target is uncovered by the radar's range (``[radar] max_range_m``), since the world has no occlusion.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..world.reference_line import Arc, Line, PlanView, Spiral
from .planar_geometry import LANE_M, ROAD_START_M, SceneCell, car, frame, parked_objects, straight_road

#: the clothoids' far-end radius (m) of Euro NCAP's turns (FC v1.1 §1.2.4: "1500 -> R2")
CLOTHOID_START_RADIUS_M = 1500.0
#: where the ego's turn starts: after the steady approach and this long (s) at its speed (crd)
TURN_AFTER_S = 4.0


def turn_path(cell: SceneCell) -> np.ndarray:
    """The ego's path in CCFtap (FC v1.1 §1.2.4): straight, clothoid 1500 m -> R, arc R, clothoid R -> 1500 m
    (a left turn of 2 clothoid_deg + arc_deg), then 80 m straight; sampled every 0.25 m, shape (k, 2)."""
    lay = cell.layout
    k1, k2 = 1.0 / CLOTHOID_START_RADIUS_M, 1.0 / lay["turn_radius_m"]
    clothoid = 2.0 * math.radians(lay["clothoid_deg"]) / (k1 + k2)  # heading change = mean curvature x length
    x_turn = cell.x0 + cell.v * (cell.t_start + TURN_AFTER_S)
    plan = PlanView.chained([Line(x_turn - ROAD_START_M), Spiral(clothoid, k1, k2),
                             Arc(math.radians(lay["arc_deg"]) * lay["turn_radius_m"], k2),
                             Spiral(clothoid, k2, k1), Line(80.0)], ROAD_START_M, 0.0, 0.0)
    x, y, _ = plan.pose(np.arange(0.0, plan.length_m, 0.25))
    return np.column_stack([x, y])


def _crossing_point(path: np.ndarray, y_m: float) -> tuple[float, float]:
    """Where ``path`` first reaches ``y = y_m`` (linear between samples): (x, path length from its start)."""
    i = int(np.argmax(path[:, 1] >= y_m))
    (x0, y0), (x1, y1) = path[i - 1], path[i]
    f = (y_m - y0) / (y1 - y0)
    s = float(np.hypot(*np.diff(path[:i], axis=0).T).sum()) + f * math.hypot(x1 - x0, y1 - y0)
    return float(x0 + f * (x1 - x0)), float(s)


def turn_across(cell: SceneCell) -> dict[str, Any]:
    """CCFtap (FC v1.1 §3.1.2): the ego turns left across the path of an oncoming GVT in lane 1 (both paths
    1.75 m from the centre line). When the ego's front is ``vut_distance_m`` before the collision point (along
    x, still on its straight) the GVT's front is ``target_distance_m`` from it (§1.2.1.1); both hold their
    speeds, so the GVT's front meets the middle of the ego's front (50 %)."""
    path = turn_path(cell)
    x_cp, _ = _crossing_point(path, LANE_M)
    t_mark = (x_cp - cell.layout["vut_distance_m"]) / cell.v  # the ego's front at X_VUT
    t_hit = t_mark + cell.layout["target_distance_m"] / cell.vt
    start = x_cp + cell.target["length_m"] / 2.0 + cell.vt * t_hit  # the GVT's centre at t = 0
    gvt = cell.target_object(trajectory={"waypoints": [[start, LANE_M], [start - cell.vt * (t_hit + 30.0), LANE_M]],
                                         "speeds": [[0.0, cell.vt]]})
    pts = path[path[:, 0] >= -5.0][::4]  # 1 m apart, from just behind the ego's start
    steering = {"model": "path_following", "waypoints": pts.tolist()}
    return frame(cell, t_hit + 3.0, straight_road(x_cp + 60.0), [gvt], steering=steering)


def crossing_car(cell: SceneCell) -> dict[str, Any]:
    """CCCscp (FC v1.1 §3.1.3): a GVT crossing the ego's path straight from the near (right) or far side,
    its front meeting the middle of the ego's front (50 %); the ``parked`` obstruction (standard range)
    stands beside the ego's road before the junction."""
    sign = 1.0 if cell.layout["side"] == "near" else -1.0
    x_sync = cell.x0 + cell.v * (cell.t_start + 4.0)
    t_sync = x_sync / cell.v
    y_centre = -sign * cell.target["length_m"] / 2.0 - sign * cell.vt * t_sync  # at t = 0
    far = sign * cell.vt * (t_sync + 30.0)
    gvt = cell.target_object(trajectory={"waypoints": [[x_sync, y_centre], [x_sync, y_centre + far]],
                                         "speeds": [[0.0, cell.vt]]})
    return frame(cell, t_sync + 3.0, straight_road(x_sync + 60.0), [gvt, *parked_objects(cell, x_sync)])


def _queue(cell: SceneCell) -> list[dict[str, Any]]:
    """``adjacent = "occupied"``: cars in lane 1 at the ego's speed, beside it and 15 m and 30 m behind (crd)."""
    if cell.layout["adjacent"] == "free":
        return []
    beside = -(cell.ego_length_m + 4.023) / 2.0  # a GVT's rear when its centre is level with the ego's
    return [{"name": f"adjacent {i + 1}", "target_class": "GVT", "position_m": beside - back,
             "speed_mps": cell.v, "lateral_m": LANE_M} for i, back in enumerate((0.0, 15.0 + 4.023, 30.0 + 2 * 4.023))]


def _reveal_radar(reveal_m: float) -> dict[str, Any]:
    return {"radar": {"max_range_m": round(max(reveal_m, 1.0), 3)}}


def cut_out_reveal(cell: SceneCell) -> dict[str, Any]:
    """A lead car ``headway_s`` ahead at the ego's speed moves to lane 1 at ``lateral_speed_mps`` when the ego's
    time to a car stopped in its lane is ``reveal_ttc_s``; the stopped car is uncovered once the lead has moved
    half the two widths across (approximated: the radar's range is the gap at that moment)."""
    lay, v = cell.layout, cell.v
    lead_len = cell.target["length_m"]
    x_stop = cell.x0 + v * (cell.t_start + 2.0 + lay["reveal_ttc_s"])  # the stopped car's rear
    t_cut = x_stop / v - lay["reveal_ttc_s"]  # the ego's front reaches reveal_ttc_s before it
    x_lead0 = lay["headway_s"] * v + lead_len / 2.0  # at the ego's speed: the phase does not move it
    x_cut = x_lead0 + v * t_cut
    ramp = v * LANE_M / lay["lateral_speed_mps"]
    lead = cell.target_object(name="lead", trajectory={
        "waypoints": [[x_lead0, 0.0], [x_cut, 0.0], [x_cut + ramp, LANE_M], [x_cut + ramp + v * 60.0, LANE_M]],
        "speeds": [[0.0, v]]})
    stopped = car("stopped car", position_m=x_stop, lateral_m=0.0)
    clear_s = (cell.target["width_m"] + cell.ego_width_m) / 2.0 / lay["lateral_speed_mps"]
    reveal = v * (lay["reveal_ttc_s"] - clear_s)
    duration = (x_stop - cell.x0) / v + 3.0
    return frame(cell, duration, straight_road(x_stop + 80.0), [lead, stopped, *_queue(cell)],
                  **_reveal_radar(reveal))


def stationary_reveal(cell: SceneCell) -> dict[str, Any]:
    """A car stopped in the ego's lane, uncovered (first within the radar's range) at the ego's time to it
    ``reveal_ttc_s``: at the test speeds braking alone cannot stop in that distance."""
    lay, v = cell.layout, cell.v
    x_stop = cell.x0 + v * (cell.t_start + 2.0 + lay["reveal_ttc_s"])
    stopped = cell.target_object(name="stopped car", position_m=x_stop, lateral_m=0.0)
    duration = (x_stop - cell.x0) / v + 3.0
    return frame(cell, duration, straight_road(x_stop + 80.0), [stopped, *_queue(cell)],
                  **_reveal_radar(v * lay["reveal_ttc_s"]))
