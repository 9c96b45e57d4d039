"""Planar catalogue cells: a series' ``scene`` builds the cell's road, objects and paths in the plane.

Frame (ISO 8855, as :mod:`cosim.scenarios.planar_config`): the ego's front bumper starts at (0, 0)
heading +x, in the middle of lane -1 (3.5 m) of a road whose reference line is y = 1.75, lane 1 (the
oncoming or overtaking lane) to its left. The robot driver holds the test speed (releasing the
accelerator after a 5 km/h drop, Euro NCAP) and keeps its lane (``path_following``) or follows the
turn's waypoints. Near side is the right (right-hand traffic, a left-hand-drive car).

A target's reference point (Euro NCAP FC v1.1 §1.1: hip, crank shaft, front) lies ``reference_m``
ahead of its box's centre; the impact location ``impact_pct`` puts it at
``y = (impact_pct / 100 - 1/2) * ego width`` on the ego's front. The encounters start after
``settle_s`` of steady driving plus the protocol's start TTC.

Radar phase ``i`` of ``N`` moves the encounter ``0.05 i/N`` s later: every x of the scene moves by
``v * shift`` (the ego reaches it later), time triggers by ``shift``, and what moves from t = 0 starts
``speed * shift`` further back along its path.

What the world cannot express is approximated in data, and each scene says so: the world has no
occlusion (an obstruction is a parked box the radar sees past; a hidden target is "uncovered" by
limiting the radar's range to the distance at which it would be uncovered).
"""

from __future__ import annotations

import math
from typing import Any, Callable, Mapping

import numpy as np

from ..scenarios.config import OBJECT_TRACK_PERIOD_S
from ..world.reference_line import Arc, Line, PlanView
from . import planar_junction as junction
from .planar_geometry import (
    KMH, LANE_M, ROAD_START_M, SceneCell, crossing_time_s, frame, impact_y, lane_centre, parked_objects, straight_road,
)


# -- Euro NCAP VRU ------------------------------------------------------------------------------------
def crossing(cell: SceneCell) -> dict[str, Any]:
    """A pedestrian or cyclist crossing the ego's path (CPNA, CPFA, CPNCO, CBNA, CBFA, CBNAO): from rest,
    its speed after ``accel_distance_m``, timed by the ego's time to the point so that its reference point
    meets ``impact_pct`` of the ego's front (the world's ``[objects.crossing]``)."""
    lay, sign = cell.layout, (1.0 if cell.layout["side"] == "near" else -1.0)
    y_imp = impact_y(cell)
    travel = lay["start_distance_m"] + sign * y_imp  # the reference point's way to the impact point
    t_target = crossing_time_s(travel, lay["accel_distance_m"], cell.vt)
    x_sync = cell.x0 + cell.v * (cell.t_start + max(float(cell.params.get("start_ttc_s", 4.0)), t_target))
    obj = cell.target_object(crossing={
        "x_m": x_sync, "y_m": y_imp - sign * lay["reference_m"], "heading_rad": sign * math.pi / 2.0,
        "start_distance_m": travel, "accel_distance_m": lay["accel_distance_m"], "speed_mps": cell.vt})
    duration = (x_sync - cell.x0) / cell.v + 2.0
    return frame(cell, duration, straight_road(x_sync + 60.0), [obj, *parked_objects(cell, x_sync)])


def along(cell: SceneCell) -> dict[str, Any]:
    """A pedestrian or cyclist ahead in the ego's lane, walking or riding away (CPLA, CBLA), its centre at
    ``impact_pct`` of the ego's width; the test ends at matched speed (Euro NCAP's longitudinal end)."""
    closing = cell.v - cell.vt
    ttc = float(cell.params.get("start_ttc_s", 4.0))
    gap = closing * (cell.t_start + ttc + cell.shift_s)
    obj = cell.target_object(position_m=gap, speed_mps=cell.vt, lateral_m=impact_y(cell))
    duration = cell.t_start + ttc + cell.v / 4.0 + 3.0
    return frame(cell, duration, straight_road(gap + cell.v * duration + 20.0), [obj], end="matched_speed")


# -- planar false positives ---------------------------------------------------------------------------------
def kerb_stop(cell: SceneCell) -> dict[str, Any]:
    """A pedestrian walks toward the road from the near side, timed as CPNA at the 50 % point, and stops at the
    kerb (its box centre at ``stop_y_m``); the ego passes."""
    lay = cell.layout
    travel = lay["start_distance_m"]
    t_cross = crossing_time_s(travel, lay["accel_distance_m"], cell.vt)
    x_sync = cell.x0 + cell.v * (cell.t_start + max(4.0, t_cross))
    y0, y1 = -travel - lay["reference_m"], lay["stop_y_m"]
    walk = y1 - y0
    slow = min(0.5, walk - lay["accel_distance_m"])  # stops within its last half metre (crd)
    speeds = [[0.0, 0.0], [lay["accel_distance_m"], cell.vt], [walk - slow, cell.vt], [walk, 0.0]]
    obj = cell.target_object(trajectory={
        "waypoints": [[x_sync, y0], [x_sync, y1 + 1.0]], "speeds": speeds, "start": "ego_ttc",
        "start_value": t_cross, "start_point": [x_sync, 0.0]})
    duration = (x_sync - cell.x0) / cell.v + 2.0
    return frame(cell, duration, straight_road(x_sync + 60.0), [obj], end="time")


def overtaken(cell: SceneCell) -> dict[str, Any]:
    """A faster car in the lane to the left, starting ``gap_m`` (negative: behind), passes the ego and stays
    in its lane."""
    lay = cell.layout
    rel = cell.vt - cell.v
    obj = cell.target_object(position_m=lay["gap_m"] - rel * cell.shift_s, speed_mps=cell.vt, lateral_m=LANE_M)
    duration = cell.t_start + (-lay["gap_m"] + cell.ego_length_m + cell.target["length_m"] + 20.0) / rel
    return frame(cell, duration, straight_road(cell.vt * duration + 40.0), [obj], end="time")


def pass_target(cell: SceneCell) -> dict[str, Any]:
    """A slower target beside the ego's path (a cyclist on the cycle lane, ``lateral_m``), passed; the road has
    a 2.0 m lane -2 on the right for it."""
    lay, closing = cell.layout, cell.v - cell.vt
    gap = closing * (cell.t_start + 4.0 + cell.shift_s)
    obj = cell.target_object(position_m=gap, speed_mps=cell.vt, lateral_m=lay["lateral_m"])
    duration = (gap + cell.ego_length_m + cell.target["length_m"] + 10.0) / closing
    road = straight_road(cell.v * duration + 40.0, right=(LANE_M, 2.0))
    return frame(cell, duration, road, [obj], end="time")


def _curve_road(cell: SceneCell, right: tuple[float, ...] = (LANE_M,)) -> tuple[dict, PlanView, float, float]:
    """A straight, an arc of ``curve_radius_m`` (the reference line's) through ``curve_angle_deg``, 300 m
    straight; the road table, its plan view, where the arc starts (s) and its curvature."""
    lay = cell.layout
    k = (1.0 if lay["curve_turn"] == "left" else -1.0) / lay["curve_radius_m"]
    first = cell.x0 - ROAD_START_M + cell.v * cell.t_start + 10.0
    arc = math.radians(lay["curve_angle_deg"]) * lay["curve_radius_m"]
    road = straight_road(ROAD_START_M + first, right=right)  # its line is `first` long: the arc starts at s = first
    road["geometry"] += [{"kind": "arc", "length_m": arc, "curvature_1pm": k}, {"kind": "line", "length_m": 300.0}]
    plan = PlanView.chained([Line(first), Arc(arc, k), Line(300.0)], ROAD_START_M, road["y_m"], 0.0)
    return road, plan, first, k


def oncoming_curve(cell: SceneCell) -> dict[str, Any]:
    """Oncoming traffic in a curve: a car in lane 1 at ``target_speed_kmh`` meets the ego ``curve_station_m``
    into the arc (in a right curve the ego's heading points at it before the road bends away)."""
    road, plan, first, _ = _curve_road(cell)
    s_meet = first + cell.layout["curve_station_m"]
    ego_path = lane_centre(plan, -LANE_M / 2.0, 0.0, s_meet)
    t_meet = _length(ego_path) / cell.v
    onc = lane_centre(plan, LANE_M / 2.0, 0.0, plan.length_m)[::-1]  # lane 1, driven toward -s
    start = _point_before(onc, _nearest(onc, lane_centre(plan, LANE_M / 2.0, s_meet, s_meet + 1.0)[0]),
                          cell.vt * t_meet)
    obj = cell.target_object(trajectory={"waypoints": onc[start:].tolist(), "speeds": [[0.0, cell.vt]]})
    return frame(cell, t_meet + 3.0, road, [obj], end="time")


def parked_curve(cell: SceneCell) -> dict[str, Any]:
    """A car parked on the outside of a curve, in a 2.5 m parking strip (lane -2), ``curve_station_m`` into
    the arc; the ego keeps its lane through the curve (the bundled ``curve_parked_car``)."""
    road, plan, first, _ = _curve_road(cell, right=(LANE_M, 2.5))
    s_car = first + cell.layout["curve_station_m"]
    obj = cell.target_object(road_pose={"s_m": s_car, "t_m": -LANE_M - 1.25})
    t_pass = _length(lane_centre(plan, -LANE_M / 2.0, 0.0, s_car)) / cell.v
    return frame(cell, t_pass + 3.0, road, [obj], end="time")


def _length(points: np.ndarray) -> float:
    return float(np.hypot(*np.diff(points, axis=0).T).sum())


def _nearest(points: np.ndarray, p: np.ndarray) -> int:
    return int(np.argmin(np.hypot(points[:, 0] - p[0], points[:, 1] - p[1])))


def _point_before(points: np.ndarray, index: int, distance_m: float) -> int:
    """The index of the point ``distance_m`` before ``points[index]`` along the polyline (or its start)."""
    back = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(points[:index + 1][::-1], axis=0).T))])
    return index - int(min(np.searchsorted(back, distance_m), index))


def lead_turns_off(cell: SceneCell) -> dict[str, Any]:
    """A lead car at the ego's speed, ``headway_s`` ahead, brakes at ``decel_mps2`` to ``turn_speed_kmh`` and
    turns right off the road (an arc of ``turn_radius_m`` through 90 degrees) into a side road."""
    lay = cell.layout
    v_turn, length = lay["turn_speed_kmh"] / KMH, cell.target["length_m"]
    x_lead = lay["headway_s"] * cell.v + length / 2.0  # at the ego's speed: the phase moves its braking instead
    brake_m = (cell.v ** 2 - v_turn ** 2) / (2.0 * lay["decel_mps2"])
    brake_at = cell.v * (cell.t_start + cell.shift_s)  # along its path
    x_turn = x_lead + brake_at + brake_m + 5.0
    plan = PlanView.chained([Line(x_turn - x_lead), Arc(lay["turn_radius_m"] * math.pi / 2.0, -1.0 / lay["turn_radius_m"]),
                             Line(200.0)], x_lead, 0.0, 0.0)
    s = np.arange(0.0, plan.length_m, 0.5)
    x, y, _ = plan.pose(s)
    speeds = [[0.0, cell.v], [brake_at, cell.v], [brake_at + brake_m, v_turn]]
    obj = cell.target_object(trajectory={"waypoints": np.column_stack([x, y]).tolist(), "speeds": speeds})
    duration = (x_turn + lay["turn_radius_m"] - cell.x0) / cell.v + 2.0
    return frame(cell, duration, straight_road(x_turn + 100.0), [obj], end="time")


#: a series' ``scene`` -> (builder, the layout keys it requires)
SCENES: dict[str, tuple[Callable[[SceneCell], dict[str, Any]], tuple[str, ...]]] = {
    "crossing": (crossing, ("impact_pct", "side", "start_distance_m", "accel_distance_m", "reference_m")),
    "along": (along, ("impact_pct",)),
    "turn_across": (junction.turn_across, ("turn_radius_m", "clothoid_deg", "arc_deg", "vut_distance_m",
                                           "target_distance_m")),
    "crossing_car": (junction.crossing_car, ("side",)),
    "cut_out_reveal": (junction.cut_out_reveal, ("headway_s", "reveal_ttc_s", "lateral_speed_mps", "adjacent")),
    "stationary_reveal": (junction.stationary_reveal, ("reveal_ttc_s", "adjacent")),
    "kerb_stop": (kerb_stop, ("start_distance_m", "accel_distance_m", "stop_y_m")),
    "overtaken": (overtaken, ("gap_m",)),
    "pass_target": (pass_target, ("lateral_m",)),
    "oncoming_curve": (oncoming_curve, ("curve_radius_m", "curve_turn", "curve_station_m")),
    "parked_curve": (parked_curve, ("curve_radius_m", "curve_turn", "curve_station_m")),
    "lead_turns_off": (lead_turns_off, ("headway_s", "decel_mps2", "turn_speed_kmh", "turn_radius_m")),
}


def scenario_dict(cell_id: str, params: Mapping[str, Any], target: Mapping[str, Any], base: Mapping[str, Any],
                  merge: Callable, phase: int, phases: int) -> dict[str, Any]:
    """The planar cell's scenario mapping at radar phase ``phase`` of ``phases``, merged over ``[scenario]``."""
    from ..scenarios.config import PlantConfig  # the ego's size: [plant] of the catalogue, else the default

    plant = base.get("plant", {})
    width = plant.get("width_m", PlantConfig.__dataclass_fields__["width_m"].default)
    length = plant.get("length_m", PlantConfig.__dataclass_fields__["length_m"].default)
    cell = SceneCell(cell_id, params, params["layout"], target, float(width), float(length),
                     OBJECT_TRACK_PERIOD_S * phase / phases)
    return merge(base, SCENES[params["scene"]][0](cell))
