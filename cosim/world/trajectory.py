"""How objects move: a path, a speed profile along it, and a trigger that starts it.

An object's motion is a pure function of time once its start time is known, and the start time
is fixed by a trigger evaluated on the ego car's state, the way Euro NCAP synchronises its
targets (Crash Avoidance – Frontal Collisions v1.1 §1.1.2, §1.5.1: the target starts so that it
reaches the synchronisation point, where its path crosses the ego's, when the ego does):

* :class:`Path`: where the object goes, a curve parametrised by its length ``s`` giving
  ``(x, y, heading, curvature)``: :class:`Polyline` through waypoints, or :class:`OffsetPath`,
  a line at constant offset ``t`` from a road's reference line (e.g. a lane centre);
* :class:`SpeedProfile`: how fast, as constant-acceleration phases built from knots either over
  path length (``v^2`` linear in ``s`` between knots, constant acceleration
  ``a = (v1^2 - v0^2) / (2 (s1 - s0))``: "5 km/h after 1.0 m of acceleration") or over time
  (``v`` linear in ``t`` between knots); after the last knot the speed stays;
* :class:`Behaviour`: a path, a profile and a trigger (:data:`TRIGGERS`): :class:`AtTime`,
  :class:`EgoTimeToPoint` (the ego's time to reach a point ``<=`` a value),
  :class:`EgoDistanceToPoint`. Until it fires the object stands at the path's start.

State and purity: the only state is the start time, a :class:`BehaviourState`;
:func:`advance` ``(behaviour, state, t, ego) -> state`` fires the trigger (once) and
:func:`kinematics` ``(behaviour, state, t) -> Kinematics`` gives the pose (x, y, yaw), the
velocity (vx, vy) over ground and the yaw rate ``v * curvature``. Both are deterministic;
call :func:`advance` once per ECU cycle as the loop samples the ego (the start time is the
first sample at which the trigger holds).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import NamedTuple, Protocol, Sequence

import numpy as np

from .road import Road


class Kinematics(NamedTuple):
    """An object's pose (m, rad), velocity over ground in world axes (m/s), yaw rate (rad/s) and speed (m/s)."""

    x_m: float
    y_m: float
    yaw_rad: float
    vx_mps: float
    vy_mps: float
    yaw_rate_radps: float
    speed_mps: float


class EgoState(NamedTuple):
    """What triggers see of the ego: its front-bumper centre (m), heading (rad) and speed (m/s)."""

    x_m: float
    y_m: float
    yaw_rad: float
    speed_mps: float


# -- paths ---------------------------------------------------------------------------------------------
class Path(Protocol):
    length_m: float

    def pose(self, s_m: float) -> tuple[float, float, float, float]:
        """(x, y, heading, curvature) at path length ``s_m``; straight on beyond the end."""


@dataclass(frozen=True)
class Polyline:
    """Straight segments through waypoints (m); heading jumps at the corners (curvature 0)."""

    points: tuple[tuple[float, float], ...]

    def __post_init__(self) -> None:
        pts = np.asarray(self.points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 2 or (np.hypot(*np.diff(pts, axis=0).T) <= 0).any():
            raise ValueError(f"polyline: expected at least 2 distinct consecutive (x, y) points, got {self.points}")
        object.__setattr__(self, "_cum", np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]))

    @property
    def length_m(self) -> float:
        return float(self._cum[-1])

    def pose(self, s_m: float) -> tuple[float, float, float, float]:
        i = min(max(bisect.bisect_right(self._cum, s_m) - 1, 0), len(self.points) - 2)
        (x0, y0), (x1, y1) = self.points[i], self.points[i + 1]
        h = math.atan2(y1 - y0, x1 - x0)
        ds = s_m - float(self._cum[i])
        return x0 + ds * math.cos(h), y0 + ds * math.sin(h), h, 0.0


@dataclass(frozen=True)
class OffsetPath:
    """The curve at offset ``t_m`` (left positive) from a road's reference line, from ``s0_m`` on, by its own length.

    Heading is the reference line's, curvature ``k / (1 - k t)`` (the offset curve of a curve of curvature
    ``k``), and its length grows as ``d sigma = (1 - k t) ds``: integrated over samples that include every
    segment joint, where ``k`` is linear in ``s`` (trapezoids are exact), and inverted per sample interval
    by solving the quadratic ``sigma - sigma_i = (1 - k_i t) u - t (k_{i+1} - k_i) u^2 / (2 Δs)``.
    """

    road: Road
    t_m: float
    s0_m: float = 0.0

    def __post_init__(self) -> None:
        plan = self.road.plan
        joints = [p.s_m for p in plan.placed] + [plan.length_m]
        s = np.unique(np.concatenate([np.arange(self.s0_m, plan.length_m, 0.5), joints, [self.s0_m]]))
        s = s[s >= self.s0_m]
        stretch = 1.0 - plan.curvature(s) * self.t_m
        if (stretch <= 0.0).any():
            raise ValueError(f"offset path: t_m={self.t_m} lies beyond the centre of curvature of the road")
        sigma = np.concatenate([[0.0], np.cumsum(0.5 * (stretch[1:] + stretch[:-1]) * np.diff(s))])
        # as lists: pose() runs for every moving object at every step, and indexing lists is cheaper
        object.__setattr__(self, "_table", (s.tolist(), sigma.tolist(), plan.curvature(s).tolist()))

    @property
    def length_m(self) -> float:
        return float(self._table[1][-1])

    def _reference_s(self, sigma_m: float) -> float:
        s, sigma, k = self._table
        if sigma_m <= 0.0 or sigma_m >= sigma[-1]:  # beyond the ends the reference line is straight
            return float(s[0] + sigma_m if sigma_m <= 0.0 else s[-1] + sigma_m - sigma[-1])
        i = min(bisect.bisect_right(sigma, sigma_m) - 1, len(s) - 2)
        d_sigma, span = sigma_m - sigma[i], s[i + 1] - s[i]
        a, b = 1.0 - k[i] * self.t_m, -self.t_m * (k[i + 1] - k[i]) / (2.0 * span)
        return float(s[i] + 2.0 * d_sigma / (a + math.sqrt(max(a * a + 4.0 * b * d_sigma, 0.0))))

    def pose(self, s_m: float) -> tuple[float, float, float, float]:
        x, y, h, k = self.road.pose_at(self._reference_s(s_m), self.t_m)
        return x, y, h, k / (1.0 - k * self.t_m)


# -- speed profiles --------------------------------------------------------------------------------------
class Phase(NamedTuple):
    """Constant acceleration from time ``t_s`` (since the motion's start), at path length ``s_m``, speed ``v_mps``."""

    t_s: float
    s_m: float
    v_mps: float
    a_mps2: float


@dataclass(frozen=True)
class SpeedProfile:
    """Constant-acceleration phases; after the last one the speed stays (see the module docstring)."""

    phases: tuple[Phase, ...]

    @classmethod
    def over_distance(cls, knots: Sequence[tuple[float, float]]) -> SpeedProfile:
        """From ``(s_m, v_mps)`` knots: constant acceleration between consecutive knots."""
        _check_knots(knots, "path length")
        phases, t = [], 0.0
        for (s0, v0), (s1, v1) in zip(knots, knots[1:]):
            if v0 + v1 <= 0.0:
                raise ValueError(f"speed profile: speed 0 at both s={s0} and s={s1}: the object never gets there")
            a = (v1 * v1 - v0 * v0) / (2.0 * (s1 - s0))
            phases.append(Phase(t, s0, v0, a))
            t += 2.0 * (s1 - s0) / (v0 + v1)  # the mean speed of a constant acceleration
        phases.append(Phase(t, knots[-1][0], knots[-1][1], 0.0))
        return cls(tuple(phases))

    @classmethod
    def over_time(cls, knots: Sequence[tuple[float, float]]) -> SpeedProfile:
        """From ``(t_s, v_mps)`` knots: speed linear in time between consecutive knots."""
        _check_knots(knots, "time")
        phases, s = [], 0.0
        if knots[0][0] > 0.0:
            phases.append(Phase(0.0, 0.0, knots[0][1], 0.0))
            s = knots[0][1] * knots[0][0]
        for (t0, v0), (t1, v1) in zip(knots, knots[1:]):
            phases.append(Phase(t0, s, v0, (v1 - v0) / (t1 - t0)))
            s += 0.5 * (v0 + v1) * (t1 - t0)
        phases.append(Phase(knots[-1][0], s, knots[-1][1], 0.0))
        return cls(tuple(phases))

    @classmethod
    def constant(cls, speed_mps: float) -> SpeedProfile:
        return cls.over_time([(0.0, speed_mps)])

    def state(self, tau_s: float) -> tuple[float, float, float]:
        """(path length (m), speed (m/s), acceleration (m/s^2)) ``tau_s`` after the start."""
        tau_s = max(tau_s, 0.0)
        p = self.phases[max(bisect.bisect_right(self.phases, tau_s, key=_phase_time) - 1, 0)]
        u = tau_s - p.t_s
        return p.s_m + p.v_mps * u + 0.5 * p.a_mps2 * u * u, p.v_mps + p.a_mps2 * u, p.a_mps2

    def time_to_reach(self, s_m: float) -> float:
        """Time (s) after the start at which the path length ``s_m`` is reached (inf: never)."""
        i = max(bisect.bisect_right(self.phases, s_m, key=_phase_s) - 1, 0)
        p = self.phases[i]
        d = s_m - p.s_m
        if p.a_mps2 == 0.0:
            return p.t_s + d / p.v_mps if p.v_mps > 0.0 else (p.t_s if d <= 0.0 else math.inf)
        # p.s + v u + a u^2 / 2 = s_m, the smallest u >= 0
        disc = p.v_mps * p.v_mps + 2.0 * p.a_mps2 * d
        return p.t_s + (math.sqrt(disc) - p.v_mps) / p.a_mps2 if disc >= 0.0 else math.inf


def _phase_time(p: Phase) -> float:
    return p.t_s


def _phase_s(p: Phase) -> float:
    return p.s_m


def _check_knots(knots: Sequence[tuple[float, float]], over: str) -> None:
    if not knots or knots[0][0] < 0.0 or any(v < 0.0 for _, v in knots) \
            or any(b[0] <= a[0] for a, b in zip(knots, knots[1:])):
        raise ValueError(f"speed profile over {over}: expected (position, speed >= 0) knots increasing"
                         f" from >= 0, got {list(knots)}")


# -- triggers -------------------------------------------------------------------------------------------------
class Trigger(Protocol):
    def holds(self, t_s: float, ego: EgoState) -> bool:
        """Whether the trigger's condition holds at ``t_s`` for the ego's state."""


@dataclass(frozen=True, slots=True)
class AtTime:
    """Starts at ``t_s`` (s)."""

    t_s: float

    def holds(self, t_s: float, ego: EgoState) -> bool:
        return t_s >= self.t_s


def ego_distance_along_m(ego: EgoState, x_m: float, y_m: float) -> float:
    """Distance (m) from the ego's front to the point's projection on its heading (negative: passed)."""
    return (x_m - ego.x_m) * math.cos(ego.yaw_rad) + (y_m - ego.y_m) * math.sin(ego.yaw_rad)


@dataclass(frozen=True, slots=True)
class EgoTimeToPoint:
    """Starts when the ego's time to reach the point, ``d / v`` with ``d`` along its heading, is <= ``ttc_s``."""

    x_m: float
    y_m: float
    ttc_s: float

    def holds(self, t_s: float, ego: EgoState) -> bool:
        d = ego_distance_along_m(ego, self.x_m, self.y_m)
        return ego.speed_mps > 0.0 and d <= self.ttc_s * ego.speed_mps


@dataclass(frozen=True, slots=True)
class EgoDistanceToPoint:
    """Starts when the ego's distance to the point along its heading is <= ``distance_m``."""

    x_m: float
    y_m: float
    distance_m: float

    def holds(self, t_s: float, ego: EgoState) -> bool:
        return ego_distance_along_m(ego, self.x_m, self.y_m) <= self.distance_m


#: trigger kind (as a scenario file will name it) -> class
TRIGGERS: dict[str, type] = {"time": AtTime, "ego_ttc": EgoTimeToPoint, "ego_distance": EgoDistanceToPoint}


# -- behaviours ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Behaviour:
    """A path and a speed profile, started by ``trigger`` (None: at t = 0)."""

    path: Path
    profile: SpeedProfile
    trigger: Trigger | None = None


class BehaviourState(NamedTuple):
    """The start time (s) of the motion, None until the trigger has fired."""

    started_at_s: float | None = None


def initial_state(behaviour: Behaviour) -> BehaviourState:
    return BehaviourState(0.0 if behaviour.trigger is None else None)


def advance(behaviour: Behaviour, state: BehaviourState, t_s: float, ego: EgoState) -> BehaviourState:
    """The state after sampling the ego at ``t_s``: the trigger fires (once) when its condition holds."""
    if state.started_at_s is not None or not behaviour.trigger.holds(t_s, ego):
        return state
    return BehaviourState(t_s)


def kinematics(behaviour: Behaviour, state: BehaviourState, t_s: float) -> Kinematics:
    """Pose, velocity and yaw rate at ``t_s``: at rest at the path's start until the motion started."""
    if state.started_at_s is None or t_s <= state.started_at_s:
        x, y, h, _ = behaviour.path.pose(0.0)
        return Kinematics(x, y, h, 0.0, 0.0, 0.0, 0.0)
    s, v, _ = behaviour.profile.state(t_s - state.started_at_s)
    x, y, h, k = behaviour.path.pose(s)
    return Kinematics(x, y, h, v * math.cos(h), v * math.sin(h), v * k, v)


def crossing(start: tuple[float, float], heading_rad: float, to_sync_m: float, speed_mps: float,
             accel_distance_m: float) -> Behaviour:
    """A target crossing straight from ``start`` along ``heading_rad``: ``speed_mps`` after ``accel_distance_m``
    of constant acceleration from rest, started when the ego's time to the synchronisation point (``to_sync_m``
    ahead of the start on the target's path) equals the target's own time to it (Euro NCAP's crossing
    scenarios, e.g. CPNA: 5 km/h after 1.0 m, sync point 4.0 m away: planar-protocol-facts.md §1.4)."""
    c, s = math.cos(heading_rad), math.sin(heading_rad)
    far = to_sync_m + 100.0  # the path goes on beyond the ego's path
    path = Polyline(((start[0], start[1]), (start[0] + far * c, start[1] + far * s)))
    profile = SpeedProfile.over_distance([(0.0, 0.0), (accel_distance_m, speed_mps)])
    sync = (start[0] + to_sync_m * c, start[1] + to_sync_m * s)
    return Behaviour(path, profile, EgoTimeToPoint(sync[0], sync[1], profile.time_to_reach(to_sync_m)))
