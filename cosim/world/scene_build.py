"""The scenario's planar tables built into world objects: the road, the scene's objects, the car's geometry.

Errors in what only the built objects can tell (a trajectory that doubles back on itself, an
offset path beyond the road's centre of curvature) are :class:`~ecu.settings.SettingError`
naming the key.
"""

from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from ecu.settings import SettingError

from ..scenarios.config import ObjectConfig, PlantConfig, Scenario
from ..scenarios.planar_config import RoadConfig, TrajectoryConfig
from .reference_line import Arc, Line, PlanView, Spiral
from .road import LaneSection, Road
from .scene_objects import BehaviourMotion, Motion, PathMotion, SceneObject
from .trajectory import (
    AtTime, Behaviour, EgoDistanceToPoint, EgoTimeToPoint, OffsetPath, Polyline, SpeedProfile, crossing,
)

#: [[road.geometry]] kind -> the segment it builds
_SEGMENTS = {
    "line": lambda g: Line(g.length_m),
    "arc": lambda g: Arc(g.length_m, g.curvature_1pm),
    "spiral": lambda g: Spiral(g.length_m, g.curvature_start_1pm, g.curvature_end_1pm),
}


def build_road(cfg: RoadConfig | None) -> Road | None:
    """The :class:`~cosim.world.road.Road` of ``[road]`` (None: no road)."""
    if cfg is None:
        return None
    plan = PlanView.chained([_SEGMENTS[g.kind](g) for g in cfg.geometry], cfg.x_m, cfg.y_m, cfg.heading_rad)
    sections = tuple(LaneSection.uniform(sec.s_m, sec.left_m, sec.right_m) for sec in cfg.lane_sections)
    return Road(plan, sections)


def lane_centre_t(road: Road, lane: int, s_m: float) -> float:
    """``t`` (m) of a lane's centre at ``s_m``, in the lane section there."""
    t = float(lane_centre_ts(road, lane, np.array([s_m]))[0])
    if math.isnan(t):
        raise SettingError("lane", f"expected a lane of the road at s = {s_m:g} m, got {lane}")
    return t


def lane_centre_ts(road: Road, lane: int, s: np.ndarray) -> np.ndarray:
    """``t`` (m) of a lane's centre at each station of ``s`` (NaN where the section there has no such lane)."""
    t = np.full_like(s, np.nan, dtype=float)
    for k, sec in enumerate(road.sections):
        end = road.sections[k + 1].s_m if k + 1 < len(road.sections) else math.inf
        m = (s >= sec.s_m) & (s < end)
        borders = sec.borders_m(s[m] - sec.s_m)
        if lane in borders:
            t[m] = 0.5 * (borders[lane][0] + borders[lane][1])
    return t


def _trajectory(cfg: TrajectoryConfig, road: Road | None) -> Behaviour:
    if cfg.lane is not None:
        t = lane_centre_t(road, cfg.lane, cfg.start_s_m) + cfg.lane_offset_m
        path = OffsetPath(road, t, cfg.start_s_m)
    else:
        path = Polyline(tuple(tuple(p) for p in cfg.waypoints))
    knots = [tuple(k) for k in cfg.speeds]
    profile = SpeedProfile.over_distance(knots) if cfg.speeds_over == "distance" else SpeedProfile.over_time(knots)
    v, p = cfg.start_value, cfg.start_point
    trigger = {"at_start": lambda: None, "time": lambda: AtTime(v), "ego_ttc": lambda: EgoTimeToPoint(p[0], p[1], v),
               "ego_distance": lambda: EgoDistanceToPoint(p[0], p[1], v)}[cfg.start]()
    return Behaviour(path, profile, trigger)


def _placed(cfg: ObjectConfig, road: Road | None) -> tuple[Motion, float]:
    """(motion, reference point -> front (m)) of one object."""
    if cfg.trajectory is not None:
        return BehaviourMotion(_trajectory(cfg.trajectory, road)), cfg.length_m / 2.0
    if cfg.crossing is not None:
        c = cfg.crossing
        start = (c.x_m - c.start_distance_m * math.cos(c.heading_rad), c.y_m - c.start_distance_m * math.sin(c.heading_rad))
        behaviour = crossing(start, c.heading_rad, c.start_distance_m, c.speed_mps, c.accel_distance_m)
        return BehaviourMotion(behaviour), cfg.length_m / 2.0
    if cfg.pose is None and cfg.road_pose is None:
        return PathMotion(cfg), cfg.length_m
    if cfg.pose is not None:
        x, y, h = cfg.pose.x_m, cfg.pose.y_m, cfg.pose.heading_rad
    else:
        rp = cfg.road_pose
        xs, ys, hs = road.pose(rp.s_m, rp.t_m)
        x, y, h = float(xs), float(ys), float(hs) + rp.heading_rad
    back = cfg.length_m / 2.0  # the pose is the centre; the frame's origin the rear
    return PathMotion(cfg, (x - back * math.cos(h), y - back * math.sin(h), h)), cfg.length_m


def build_objects(scenario: Scenario, road: Road | None) -> list[SceneObject]:
    """The scene's objects, in the order of ``[[objects]]`` (disabled ones left out)."""
    objects = []
    for cfg in scenario.scene_objects():
        try:
            motion, front = _placed(cfg, road)
        except ValueError as exc:
            raise SettingError(f"objects.{cfg.name}", str(exc)) from None
        objects.append(SceneObject(len(objects), cfg, motion, front))
    return objects


def vehicle_geometry(plant: PlantConfig) -> Mapping[str, float]:
    """The builtin plant's wheelbase, CG to rear axle, steering ratio and road-wheel angle limit, with
    ``[plant.parameters]`` applied (fmu_plant/src/variables.def holds the defaults)."""
    from fmu_plant.variables import BY_NAME

    p = {name: float(plant.parameters.get(name, BY_NAME[name].start))
         for name in ("wheelbase", "cg_to_front_axle", "steering_ratio", "steering_angle_max")}
    return {"wheelbase_m": p["wheelbase"], "cg_to_rear_axle_m": p["wheelbase"] - p["cg_to_front_axle"],
            "steering_ratio": p["steering_ratio"], "max_road_wheel_angle_rad": p["steering_angle_max"]}


def polyline(points: np.ndarray) -> np.ndarray:
    """``points`` (k, 2) without NaN rows and without repeated consecutive points."""
    points = points[~np.isnan(points).any(axis=1)]
    keep = np.concatenate([[True], np.hypot(*np.diff(points, axis=0).T) > 1e-9])
    return points[keep]
