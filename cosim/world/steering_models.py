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
_WINDOW_BEHIND = 5  # points of the followed line kept behind the front bumper's nearest one (the rear axle's too)
_WINDOW_SLACK_M = 20.0  # the window reaches this far beyond the longest look-ahead


def held(cfg: SteeringConfig, road: Road | None, plant: PlantConfig) -> SteeringModel:
    """The wheel held at ``angle_rad`` whatever happens (0: the paper's distracted driver)."""
    angle = cfg.angle_rad
    return lambda t_s, ego: angle


class PathFollower:
    """Pure pursuit along a lane or waypoints, with the lane changes of the configuration (module docstring).

    Pure pursuit searches its path for the point nearest the rear axle; here it gets a window of the followed
    line (from a few points behind the car to well beyond the longest look-ahead), moved on as the car
    advances, and the nearest point, found from last cycle's by looking at its neighbours: a long road costs
    no more than a short one. A lane change's station is the front bumper's: the rear axle's on the line
    plus the distance between them.
    """

    def __init__(self, cfg: SteeringConfig, road: Road | None, geometry: Mapping[str, float],
                 front_m: float) -> None:
        self.params = PurePursuitParams(
            **geometry, lookahead_time_s=cfg.lookahead_time_s, lookahead_min_m=cfg.lookahead_min_m,
            lookahead_max_m=cfg.lookahead_max_m)
        self._road, self._changes = road, list(cfg.lane_changes)
        self._front_m = front_m  # centre of gravity -> front bumper
        self._rear = (math.inf, math.inf)  # the rear axle, once a cycle has seen the car
        if cfg.lane is None:
            points = polyline(np.array(cfg.waypoints, dtype=float))
            self._set_line(points, np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(points, axis=0).T))]))
            return
        s = np.arange(0.0, road.length_m + STATION_STEP_M, STATION_STEP_M)
        self._follow(s, lane_centre_ts(road, cfg.lane, s))

    def _follow(self, s: np.ndarray, t: np.ndarray) -> None:
        """Follow the line at offsets ``t`` from the road's reference line at stations ``s``."""
        keep = ~np.isnan(t)
        x, y, _ = self._road.pose(s[keep], t[keep])
        self._offsets = t[keep]
        self._set_line(np.column_stack([x, y]), s[keep])

    def _set_line(self, points: np.ndarray, stations: np.ndarray) -> None:
        self._points, self._stations = points, stations
        self._start = 0
        reach = self.params.lookahead_max_m + _WINDOW_SLACK_M
        spacing = float(np.min(np.hypot(*np.diff(points, axis=0).T)))
        self._span = max(4, int(math.ceil(reach / spacing)) + _WINDOW_BEHIND)
        self._window()

    def _window(self, search: bool = True) -> None:
        end = min(len(self._points), self._start + self._span)
        start = max(0, min(self._start, end - 2))
        self._start, self.path = start, Path.from_points(self._points[start:end, 0], self._points[start:end, 1])
        self._xs, self._ys = self.path.x_m.tolist(), self.path.y_m.tolist()
        self._near = 0
        if search:  # a new line: where the car is on it, found by the whole search once
            self._near = int(np.argmin(np.hypot(self.path.x_m - self._rear[0], self.path.y_m - self._rear[1])))
            self._near = min(self._near, len(self._xs) - 2)

    def _segment(self, k: int, x_m: float, y_m: float) -> tuple[float, float]:
        """(squared distance, fraction) of the window's segment ``k`` to its point nearest (x, y)."""
        px, py = self._xs, self._ys
        dx, dy = px[k + 1] - px[k], py[k + 1] - py[k]
        f = min(max(((x_m - px[k]) * dx + (y_m - py[k]) * dy) / (dx * dx + dy * dy), 0.0), 1.0)
        return (px[k] + f * dx - x_m) ** 2 + (py[k] + f * dy - y_m) ** 2, f

    def _nearest(self, x_m: float, y_m: float) -> tuple[int, float]:
        """The window's segment nearest (x, y) and the fraction along it: from the last one found, on to the
        neighbours while they are nearer (the car moves less than a segment per cycle)."""
        k, last = self._near, len(self._xs) - 2
        d2, f = self._segment(k, x_m, y_m)
        for step in (1, -1):
            while 0 <= k + step <= last:
                d2_next, f_next = self._segment(k + step, x_m, y_m)
                if d2_next >= d2:
                    break
                k, d2, f = k + step, d2_next, f_next
        self._near = k
        return k, f

    def station_m(self, k: int, f: float) -> float:
        """The station (s along the road, or along the waypoints) of the window's point (segment ``k``, fraction ``f``)."""
        i = k + self._start
        return float(self._stations[i] + f * (self._stations[i + 1] - self._stations[i]))

    def _due(self, change: LaneChangeConfig, t_s: float, station_m: float) -> bool:
        return t_s >= change.at_time_s if change.at_time_s is not None else station_m >= change.at_station_m

    def _change(self, change: LaneChangeConfig, s0_m: float) -> None:
        """Follow the line moving across to ``change.to_lane`` from station ``s0_m`` (module docstring)."""
        s = np.arange(max(0.0, s0_m - _BEHIND_M), self._road.length_m + STATION_STEP_M, STATION_STEP_M)
        t_from = np.interp(s, self._stations, self._offsets)
        t_to = lane_centre_ts(self._road, change.to_lane, s)
        u = np.clip((s - s0_m) / change.length_m, 0.0, 1.0)
        self._follow(s, t_from + (t_to - t_from) * 0.5 * (1.0 - np.cos(math.pi * u)))

    def __call__(self, t_s: float, ego: Ego) -> float:
        back = self.params.cg_to_rear_axle_m
        self._rear = (ego.x_m - back * ego.cos_yaw, ego.y_m - back * ego.sin_yaw)
        k, f = self._nearest(*self._rear)
        if self._changes and self._due(self._changes[0], t_s, self.station_m(k, f) + back + self._front_m):
            self._change(self._changes.pop(0), self.station_m(k, f) + back + self._front_m)
            k, f = self._nearest(*self._rear)
        elif k > _WINDOW_BEHIND and self._start + self._span < len(self._points):  # slide the window on
            self._start += k - _WINDOW_BEHIND
            self._window(search=False)
            self._near = k = _WINDOW_BEHIND
        pose = Pose(ego.x_m, ego.y_m, ego.yaw_rad)
        return pursuit(pose, max(ego.speed_mps, 0.0), self.path, self.params, (k, f)).steering_wheel_angle_rad


def path_following(cfg: SteeringConfig, road: Road | None, plant: PlantConfig) -> SteeringModel:
    """Pure pursuit along the centre of ``lane`` of ``[road]`` or along ``waypoints``, with ``lane_changes``
    (module docstring). Its vehicle geometry is the builtin plant's unless given."""
    geometry = dict(vehicle_geometry(plant)) if plant.fmu == "builtin" else {}
    for key in ("wheelbase_m", "cg_to_rear_axle_m", "steering_ratio", "max_road_wheel_angle_rad"):
        if getattr(cfg, key) is not None:
            geometry[key] = getattr(cfg, key)
    return PathFollower(cfg, road, geometry, plant.front_m)


STEERING_MODELS: dict[str, Callable[[SteeringConfig, Road | None, PlantConfig], SteeringModel]] = {
    "held": held,
    "path_following": path_following,
}


def make_steering(cfg: SteeringConfig | None, road: Road | None, plant: PlantConfig) -> SteeringModel | None:
    """The steering model of ``[driver.steering]``; None without one (the wheel held straight)."""
    return None if cfg is None else STEERING_MODELS[cfg.model](cfg, road, plant)
