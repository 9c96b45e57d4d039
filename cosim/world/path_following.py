"""A path-following driver: pure pursuit, from the car's pose and speed to a steering-wheel angle.

Pure and stateless: :func:`steering_wheel_angle` maps (pose, speed, path, parameters) to the
steering-wheel angle a driver would hold, so lane keeping, lane changes and path following are
all "follow this :class:`Path`". It imports numpy only.

Pure pursuit (R. C. Coulter, "Implementation of the Pure Pursuit Path Tracking Algorithm",
CMU-RI-TR-92-01, 1992): from the rear axle, take the goal point on the path at the look-ahead
distance ``l`` ahead of the nearest point; the circular arc through the rear axle, tangent to the
heading, that reaches the goal point has the curvature ``gamma = 2 x / l**2``, where ``x`` is the
goal point's lateral offset in the vehicle frame. The kinematic single-track model turns on that
arc with the road-wheel angle ``delta = atan(L gamma)`` (L the wheelbase); the steering-wheel
angle is ``i_s delta``. The look-ahead grows with speed, ``l = clip(t_l v, l_min, l_max)``, as in
J. M. Snider, "Automatic Steering Methods for Autonomous Automobile Path Tracking",
CMU-RI-TR-09-08, 2009, section 2.2.

Limits: the nearest point is searched over the whole path, so a path must not pass within the
look-ahead distance of itself elsewhere (no hairpins tighter than that, no closed loops). Past
the path's end the goal point lies on the extension of its last segment.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Path", "Pose", "PurePursuitParams", "PursuitResult", "pursuit", "steering_wheel_angle"]


class PathError(ValueError):
    """A path or a parameter set the pure-pursuit driver cannot use."""


@dataclass(frozen=True)
class Pose:
    """The car's centre of gravity in the world frame and its heading (counter-clockwise from x)."""

    x_m: float
    y_m: float
    yaw_rad: float


@dataclass(frozen=True, eq=False)
class Path:
    """A polyline in the world frame, in driving order; build it with :meth:`from_points`."""

    x_m: np.ndarray
    y_m: np.ndarray

    @classmethod
    def from_points(cls, x_m, y_m) -> "Path":
        """Validate and freeze the points: at least two, finite, consecutive points apart."""
        x = np.array(x_m, dtype=float)
        y = np.array(y_m, dtype=float)
        if x.ndim != 1 or x.shape != y.shape or x.size < 2:
            raise PathError(f"path: expected two equal 1-D sequences of >= 2 points, got shapes {x.shape}, {y.shape}")
        if not (np.isfinite(x).all() and np.isfinite(y).all()):
            raise PathError("path: expected finite coordinates, got NaN or inf")
        seg = np.hypot(np.diff(x), np.diff(y))
        if (seg <= 0.0).any():
            index = int(np.argmin(seg)) + 1
            raise PathError(f"path: consecutive points must differ; point {index} repeats the one before")
        x.flags.writeable = False
        y.flags.writeable = False
        return cls(x, y)


@dataclass(frozen=True)
class PurePursuitParams:
    """Vehicle geometry and the driver's look-ahead; defaults are the crd plant's
    (fmu_plant/README.md) and a look-ahead of 0.5 s of travel."""

    wheelbase_m: float = 2.7
    cg_to_rear_axle_m: float = 1.5
    steering_ratio: float = 16.0
    max_road_wheel_angle_rad: float = 1.066
    lookahead_time_s: float = 0.5
    lookahead_min_m: float = 3.0
    lookahead_max_m: float = 40.0

    def __post_init__(self) -> None:
        positive = ("wheelbase_m", "steering_ratio", "max_road_wheel_angle_rad", "lookahead_time_s", "lookahead_min_m")
        for name in positive:
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise PathError(f"PurePursuitParams.{name}: expected a finite number > 0, got {value!r}")
        if not 0.0 <= self.cg_to_rear_axle_m <= self.wheelbase_m:
            raise PathError(f"PurePursuitParams.cg_to_rear_axle_m: expected 0..wheelbase_m "
                            f"({self.wheelbase_m}), got {self.cg_to_rear_axle_m!r}")
        if not self.lookahead_max_m >= self.lookahead_min_m:
            raise PathError(f"PurePursuitParams.lookahead_max_m: expected >= lookahead_min_m "
                            f"({self.lookahead_min_m}), got {self.lookahead_max_m!r}")


@dataclass(frozen=True)
class PursuitResult:
    """One pure-pursuit decision: the angles, the goal point and the rear axle's cross-track error
    (signed, positive when the path lies to the car's left)."""

    steering_wheel_angle_rad: float
    road_wheel_angle_rad: float
    goal_x_m: float
    goal_y_m: float
    lookahead_m: float
    cross_track_m: float


def _nearest(path: Path, qx: float, qy: float) -> tuple[int, float, float]:
    """Segment index, fraction along it and squared distance of the point of ``path`` nearest (qx, qy)."""
    x0, y0 = path.x_m[:-1], path.y_m[:-1]
    dx, dy = np.diff(path.x_m), np.diff(path.y_m)
    t = np.clip(((qx - x0) * dx + (qy - y0) * dy) / (dx * dx + dy * dy), 0.0, 1.0)
    d2 = (x0 + t * dx - qx) ** 2 + (y0 + t * dy - qy) ** 2
    k = int(np.argmin(d2))
    return k, float(t[k]), float(d2[k])


def _goal(path: Path, k: int, t: float, q: tuple[float, float], lookahead_m: float) -> tuple[float, float]:
    """First point at distance ``lookahead_m`` from q walking forward from segment k, fraction t.

    On the segment a + s (b - a), s in [s0, 1], it solves |a + s (b - a) - q| = l for the larger
    root; past the last point the last segment is extended."""
    qx, qy = q
    for i in range(k, len(path.x_m) - 1):
        ax, ay, bx, by = path.x_m[i], path.y_m[i], path.x_m[i + 1], path.y_m[i + 1]
        last = i == len(path.x_m) - 2
        if not last and math.hypot(bx - qx, by - qy) < lookahead_m:
            continue
        dx, dy, fx, fy = bx - ax, by - ay, ax - qx, ay - qy
        a = dx * dx + dy * dy
        b = 2.0 * (fx * dx + fy * dy)
        c = fx * fx + fy * fy - lookahead_m * lookahead_m
        s = (-b + math.sqrt(max(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)
        s = max(s, t if i == k else 0.0)
        return ax + s * dx, ay + s * dy
    raise AssertionError("unreachable: the last segment always yields a goal point")


def pursuit(pose: Pose, speed_mps: float, path: Path, params: PurePursuitParams,
            near: tuple[int, float] | None = None) -> PursuitResult:
    """Pure pursuit (Coulter 1992): ``delta = atan(L * 2 x / l**2)``, ``l = clip(t_l v, l_min, l_max)``.

    ``x`` is the goal point's lateral offset from the rear axle in the vehicle frame; the result
    is limited to the road-wheel angle limit. ``near``: the path's point nearest the rear axle as
    (segment, fraction), when the caller tracks it (else it is searched over the whole path)."""
    if not (math.isfinite(speed_mps) and speed_mps >= 0.0):
        raise PathError(f"speed_mps: expected a finite number >= 0, got {speed_mps!r}")
    c, s = math.cos(pose.yaw_rad), math.sin(pose.yaw_rad)
    q = (pose.x_m - params.cg_to_rear_axle_m * c, pose.y_m - params.cg_to_rear_axle_m * s)
    lookahead = min(max(params.lookahead_time_s * speed_mps, params.lookahead_min_m), params.lookahead_max_m)
    k, t = near if near is not None else _nearest(path, *q)[:2]
    gx, gy = _goal(path, k, t, q, lookahead)
    lateral = -s * (gx - q[0]) + c * (gy - q[1])
    delta = math.atan(params.wheelbase_m * 2.0 * lateral / (lookahead * lookahead))
    delta = min(max(delta, -params.max_road_wheel_angle_rad), params.max_road_wheel_angle_rad)
    px = path.x_m[k] + t * (path.x_m[k + 1] - path.x_m[k])
    py = path.y_m[k] + t * (path.y_m[k + 1] - path.y_m[k])
    cross = -s * (px - q[0]) + c * (py - q[1])
    return PursuitResult(params.steering_ratio * delta, delta, gx, gy, lookahead, cross)


def steering_wheel_angle(pose: Pose, speed_mps: float, path: Path, params: PurePursuitParams) -> float:
    """The steering-wheel angle (rad, positive left) that follows ``path``: :func:`pursuit`'s."""
    return pursuit(pose, speed_mps, path, params).steering_wheel_angle_rad
