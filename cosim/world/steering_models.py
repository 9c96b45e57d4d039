"""Steering models: the driver's hands on the wheel, as a steering-wheel angle once per ECU cycle.

``[driver] model`` makes the pedals (:mod:`cosim.world.driver_models`); ``[driver.steering]`` names one
of :data:`STEERING_MODELS` for the wheel, and without it the wheel is held straight (the paper's
distracted driver: full throttle, wheel held). The angle goes to the plant's ``steering_wheel_angle``
through the gateway's driver pass-through; the ECU does not see it yet (``DriverInput`` carries 0).

``path_following`` steers with pure pursuit (:mod:`cosim.world.path_following`: Coulter 1992, the
look-ahead growing with speed as in Snider 2009) along a lane's centre or along waypoints. A lane
change moves the followed line across to the new lane's centre over ``length_m`` of road, its offset
a half cosine of the distance travelled (ASAM OpenSCENARIO 1.x ``LaneChangeAction`` with
``TransitionDynamics`` shape ``sinusoidal``, dimension ``distance``)::

    t(s) = t_from(s) + (t_to(s) - t_from(s)) (1 - cos(pi (s - s0) / L)) / 2,    s0 <= s <= s0 + L

from ``s0``, the station of the front bumper when the change starts (at its time, or once the front
bumper reaches its station).
"""

from __future__ import annotations

import math
from typing import Callable, Mapping

import numpy as np

from ..scenarios.config import PlantConfig
from ..scenarios.planar_config import LaneChangeConfig, SteeringConfig
from .ego import Ego
from .path_following import Path, Pose, PurePursuitParams, pursuit
from .road import Road
from .scene_build import lane_centre_ts, polyline, vehicle_geometry

SteeringModel = Callable[[float, Ego], float]
"""``model(t_s, ego) -> steering-wheel angle (rad, positive left)``."""

#: spacing (m) of the stations a followed lane is sampled at (a 100 m radius is off the chords by 5 mm)
STATION_STEP_M = 2.0
_BEHIND_M = 10.0  # a lane change's path starts this far behind the front bumper's station


def held(cfg: SteeringConfig, road: Road | None, plant: PlantConfig) -> SteeringModel:
    """The wheel held at ``angle_rad`` whatever happens (0: the paper's distracted driver)."""
    angle = cfg.angle_rad
    return lambda t_s, ego: angle


class PathFollower:
    """Pure pursuit along a lane or waypoints, with the lane changes of the configuration (module docstring)."""

    def __init__(self, cfg: SteeringConfig, road: Road | None, geometry: Mapping[str, float]) -> None:
        self.params = PurePursuitParams(
            **geometry, lookahead_time_s=cfg.lookahead_time_s, lookahead_min_m=cfg.lookahead_min_m,
            lookahead_max_m=cfg.lookahead_max_m)
        self._road, self._changes = road, list(cfg.lane_changes)
        if cfg.lane is None:
            self._stations = None
            self.path = Path.from_points(*np.array(cfg.waypoints, dtype=float).T)
            return
        self._lane = cfg.lane
        s = np.arange(0.0, road.length_m + STATION_STEP_M, STATION_STEP_M)
        self._follow(s, lane_centre_ts(road, cfg.lane, s))

    def _follow(self, s: np.ndarray, t: np.ndarray) -> None:
        x, y, _ = self._road.pose(s, t)
        keep = ~np.isnan(t)
        self._stations, self._offsets = s[keep], t[keep]
        points = polyline(np.column_stack([x[keep], y[keep]]))
        self.path = Path.from_points(points[:, 0], points[:, 1])

    def station_m(self, x_m: float, y_m: float) -> float:
        """The station (s along the road) of the followed line's point nearest (x, y)."""
        px, py = self.path.x_m, self.path.y_m
        dx, dy = np.diff(px), np.diff(py)
        f = np.clip(((x_m - px[:-1]) * dx + (y_m - py[:-1]) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
        k = int(np.argmin((px[:-1] + f * dx - x_m) ** 2 + (py[:-1] + f * dy - y_m) ** 2))
        return float(self._stations[k] + f[k] * (self._stations[k + 1] - self._stations[k]))

    def _due(self, change: LaneChangeConfig, t_s: float, ego: Ego) -> bool:
        if change.at_time_s is not None:
            return t_s >= change.at_time_s
        return self.station_m(ego.front_x_m, ego.front_y_m) >= change.at_station_m

    def _change(self, change: LaneChangeConfig, s0_m: float) -> None:
        """Follow the line moving across to ``change.to_lane`` from station ``s0_m`` (module docstring)."""
        s = np.arange(max(0.0, s0_m - _BEHIND_M), self._road.length_m + STATION_STEP_M, STATION_STEP_M)
        t_from = np.interp(s, self._stations, self._offsets)
        t_to = lane_centre_ts(self._road, change.to_lane, s)
        u = np.clip((s - s0_m) / change.length_m, 0.0, 1.0)
        self._follow(s, t_from + (t_to - t_from) * 0.5 * (1.0 - np.cos(math.pi * u)))
        self._lane = change.to_lane

    def __call__(self, t_s: float, ego: Ego) -> float:
        if self._changes and self._due(self._changes[0], t_s, ego):
            self._change(self._changes.pop(0), self.station_m(ego.front_x_m, ego.front_y_m))
        pose = Pose(ego.x_m, ego.y_m, ego.yaw_rad)
        return pursuit(pose, max(ego.speed_mps, 0.0), self.path, self.params).steering_wheel_angle_rad


def path_following(cfg: SteeringConfig, road: Road | None, plant: PlantConfig) -> SteeringModel:
    """Pure pursuit along the centre of ``lane`` of ``[road]`` or along ``waypoints``, with ``lane_changes``
    (module docstring). Its vehicle geometry is the builtin plant's unless given."""
    geometry = dict(vehicle_geometry(plant)) if plant.fmu == "builtin" else {}
    for key in ("wheelbase_m", "cg_to_rear_axle_m", "steering_ratio", "max_road_wheel_angle_rad"):
        if getattr(cfg, key) is not None:
            geometry[key] = getattr(cfg, key)
    return PathFollower(cfg, road, geometry)


STEERING_MODELS: dict[str, Callable[[SteeringConfig, Road | None, PlantConfig], SteeringModel]] = {
    "held": held,
    "path_following": path_following,
}


def make_steering(cfg: SteeringConfig | None, road: Road | None, plant: PlantConfig) -> SteeringModel | None:
    """The steering model of ``[driver.steering]``; None without one (the wheel held straight)."""
    return None if cfg is None else STEERING_MODELS[cfg.model](cfg, road, plant)
