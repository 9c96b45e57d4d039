"""An object's ``<FollowTrajectoryAction>`` as crd's ``[objects.trajectory]``, or as ``[objects.crossing]``.

What the object does: the trajectory (in Init: it starts at t = 0; in the story: at its event's
condition), and at most one ``<SpeedAction>`` in the same event. crd reads:

* the path: the polyline's vertices moved to the box centre (:func:`.trajectory.centre_path`), in
  crd's frame. A polyline of lane positions of one lane and one offset on the road that is the
  scenario's ``[road]``, ``s`` increasing to the road's end, of an object whose box centre is its
  reference point, is the lane itself (``lane``, ``lane_offset_m``, ``start_s_m``) when every chord
  stays within :data:`CHORD_TOL_M` of the lane (its sagitta ``c^2 |k| / 8``, ``k`` the lane's
  largest curvature between the two vertices): the file's tools follow the chords, crd the lane;
* the speed: ``<TimeReference><None/>``: the Init speed, and a linear ``SpeedAction`` over a
  distance ``d`` to ``v1`` makes it ``[[0, v0], [d, v1]]`` (constant acceleration over path length,
  as crd's knots); further linear ``SpeedAction`` events started by the object's own
  ``TraveledDistanceCondition`` add knots (:mod:`.speed_segments`); ``<Timing>``: vertex ``i`` is reached at ``T_i = offset + scale tau_i``
  (relative: after the start), so each segment's speed is ``L_i / (T_i+1 - T_i)``. crd's profile
  changes speed with a constant acceleration, not in steps, so all those speeds must be one speed
  (within :data:`SPEED_TOL`); the motion then starts at ``T_0``. Other timings are a one-line error;
* the start: Init -> ``at_start``; ``SimulationTimeCondition`` -> ``time``; the ego's
  ``TimeToCollisionCondition`` to a position with ``freespace`` -> ``ego_ttc`` at that point.

A crossing is the trajectory whose numbers are those of :func:`cosim.world.trajectory.crossing`:
standing at the start, heading ``h``; the polyline start -> synchronisation point -> end on that
heading, the point ``d`` from the start and the end ``d + 100`` m; a linear ``SpeedAction`` over
the acceleration distance; and the ego's time to the point equal to the object's own time to it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from ...world.trajectory import crossing
from .actions import SpeedChange
from .conditions import AtTime, AtTtcPoint
from .entities import Body
from .frame import Frame
from .opendrive import Road
from .positions import Pose
from .speed_segments import OverlapError, Segment, knots
from .trajectory import FollowTrajectory, centre_path
from .xml_source import unsupported

VERTEX_TOL_M = 1e-3
CHORD_TOL_M = 0.05
SPEED_TOL = 1e-6
MATCH_TOL = 1e-9
DISTANCE_ULPS = 64


@dataclass(frozen=True)
class Motion:
    """What an object does: its trajectory, and how it starts and changes speed."""

    follow: FollowTrajectory
    start: Any  #: None: the trajectory is an Init action
    speed: SpeedChange | None  #: in the trajectory's event
    body: Body
    init_speed_mps: float
    init_h_rad: float
    later: tuple[tuple[float, SpeedChange], ...] = ()  #: (path length, change) by TraveledDistanceCondition


def _crd(frame: Frame, x: float, y: float) -> list[float]:
    return [frame.along(x, y) - frame.ego_front_m, frame.across(x, y) - frame.ego.centre_y_m]


def _start(motion: Motion, frame: Frame, ego: str) -> dict[str, Any]:
    start = motion.start
    if start is None:
        return {"start": "at_start"}
    if isinstance(start, AtTime):
        return {"start": "time", "start_value": start.t_s}
    if isinstance(start, AtTtcPoint) and start.entity == ego and start.freespace:
        return {"start": "ego_ttc", "start_value": start.ttc_s, "start_point": _crd(frame, start.pose.x_m, start.pose.y_m)}
    raise unsupported(start.elem, "a trajectory started by this condition: crd starts one at a time, or by the "
                                  "ego's time to collision with a position (freespace)")


def _lane_path(motion: Motion, road: Road | None) -> dict[str, Any] | None:
    """``lane``, ``lane_offset_m``, ``start_s_m`` if the polyline is a lane (module docstring), else None."""
    spots = [p.spot for p in motion.follow.poses]
    body = motion.body
    if road is None or body.centre_x_m != 0.0 or body.centre_y_m != 0.0 or any(
            s is None or s.lane is None or s.road_id != road.road_id for s in spots):
        return None
    if len({(s.lane, s.offset_m) for s in spots}) != 1 or any(b.s_m <= a.s_m for a, b in zip(spots, spots[1:])):
        return None
    if abs(spots[-1].s_m - road.plan.length_m) > VERTEX_TOL_M:
        return None
    for (a, b), (pa, pb) in zip(zip(spots, spots[1:]), zip(motion.follow.vertices, motion.follow.vertices[1:])):
        k = max_curvature(road, a.s_m, b.s_m)
        k_lane = k / max(1.0 - k * abs(a.t_m), 1e-9)
        if math.dist(pa, pb) ** 2 * k_lane / 8.0 > CHORD_TOL_M:
            return None
    return {"lane": spots[0].lane, "lane_offset_m": spots[0].offset_m, "start_s_m": spots[0].s_m}


def max_curvature(road: Road, s0_m: float, s1_m: float) -> float:
    """The largest ``|k|`` of the reference line between two stations (lines and arcs constant, spirals linear)."""
    k = 0.0
    for p in road.plan.placed:
        lo, hi = max(s0_m, p.s_m), min(s1_m, p.s_m + p.segment.length_m)
        if hi > lo:
            k = max(k, abs(p.segment.curvature_at(lo - p.s_m)), abs(p.segment.curvature_at(hi - p.s_m)))
    return k


def _timed(motion: Motion, keys: dict[str, Any]) -> dict[str, Any]:
    """The constant speed and the start time a ``<Timing>`` gives (module docstring)."""
    timing, times, pts = motion.follow.timing, motion.follow.times, motion.follow.vertices
    by_ttc = keys["start"] == "ego_ttc"  # the start is a condition, not a time: the times must start with it
    if by_ttc and (timing.absolute or timing.offset_s + timing.scale * times[0] != 0.0):
        raise unsupported(timing.elem, "vertex times that do not start with the action started by a condition")
    begin = 0.0 if by_ttc else keys.get("start_value", 0.0)
    at = [timing.offset_s + timing.scale * t + (0.0 if timing.absolute else begin) for t in times]
    if at[0] < begin or any(b <= a for a, b in zip(at, at[1:])):
        raise unsupported(timing.elem, f"vertex times {at}: crd's object starts at the first vertex, then moves on")
    lengths = [math.dist(a, b) for a, b in zip(pts, pts[1:])]
    speed = sum(lengths) / (at[-1] - at[0])
    steps = [length / (b - a) for length, a, b in zip(lengths, at, at[1:])]
    if any(abs(v - speed) > SPEED_TOL * max(speed, 1.0) for v in steps):
        raise unsupported(timing.elem, f"vertex times giving speeds {[round(v, 6) for v in steps]} m/s: crd's "
                                       "trajectory changes speed with a constant acceleration, not in steps")
    if not by_ttc and (at[0] > 0.0 or keys["start"] != "at_start"):
        keys = keys | {"start": "time", "start_value": at[0]}
    return keys | {"speeds": [[0.0, speed]]}


def _speeds(motion: Motion) -> list[list[float]]:
    """The knots of the Init speed and the speed changes (:mod:`.speed_segments`)."""
    later = sorted(motion.later, key=lambda pair: pair[0])
    if later and motion.start is not None and (motion.init_speed_mps > 0.0 or later[0][0] == 0.0):
        raise unsupported(later[0][1].elem, "a speed change by travelled distance along a trajectory started in the "
                                            "story: crd reads one from a start at rest and a distance > 0 (the "
                                            "distance counts from t = 0)")
    changes = ([(0.0, motion.speed)] if motion.speed is not None else []) + later
    segs = []
    for start_m, change in changes:
        dyn = change.dynamics
        if dyn.shape != "linear" or dyn.dimension != "distance" or dyn.value <= 0.0:
            raise unsupported(dyn.elem, "a speed change along a trajectory: crd reads a linear one over a distance")
        segs.append(Segment(start_m, dyn.value, change.target_mps))
    try:
        return knots(motion.init_speed_mps, segs)
    except OverlapError as exc:
        raise unsupported(changes[exc.index][1].elem, str(exc)) from None


def trajectory_keys(motion: Motion, start_pose: Pose, frame: Frame, road: Road | None, ego: str) -> dict[str, Any]:
    """``{"trajectory": ...}`` or ``{"crossing": ...}`` for an object's motion (module docstring)."""
    follow = motion.follow
    if math.hypot(start_pose.x_m - follow.vertices[0][0], start_pose.y_m - follow.vertices[0][1]) > VERTEX_TOL_M:
        raise unsupported(follow.elem, f"{motion.body.name!r} starts off its trajectory's first vertex: crd's "
                                       "objects stand at their path's start until they move")
    keys = _start(motion, frame, ego)
    if follow.timing is not None and (motion.speed is not None or motion.later):
        change = motion.speed if motion.speed is not None else motion.later[0][1]
        raise unsupported(change.elem, "a speed action with a timed trajectory: the vertex times give the speed")
    keys = _timed(motion, keys) if follow.timing is not None else keys | {"speeds": _speeds(motion)}
    crossed = _crossing(motion, keys, frame)
    if crossed is not None:
        return {"crossing": crossed}
    lane = _lane_path(motion, road)
    if lane is None:
        body = motion.body
        lane = {"waypoints": [_crd(frame, x, y)
                              for x, y in centre_path(follow.vertices, body.centre_x_m, body.centre_y_m)]}
    return {"trajectory": lane | keys | {"speeds_over": "distance"}}


def exact_distance(start: tuple[float, float], point: tuple[float, float], h_rad: float) -> float:
    """The distance ``d`` from ``start`` to ``point`` on heading ``h``, as the number crd's crossing was given.

    crd places the start at ``point - d (cos h, sin h)``, rounded; many floats next to ``|point - start|``
    give that start bit for bit, so the file alone cannot tell them apart. Of those within
    :data:`DISTANCE_ULPS` units in the last place, this takes the one with the shortest decimal form
    (the number a scenario file holds: 6.7, not 6.700000000000001), the nearest on a tie; none: the distance.
    """
    d = math.dist(start, point)
    c, s = math.cos(h_rad), math.sin(h_rad)
    candidates, lo, hi = [d], d, d
    for _ in range(DISTANCE_ULPS):
        lo, hi = math.nextafter(lo, -math.inf), math.nextafter(hi, math.inf)
        candidates += [lo, hi]
    exact = [x for x in candidates if (point[0] - x * c, point[1] - x * s) == tuple(start)]
    return min(exact, key=lambda x: (len(repr(x)), abs(x - d)), default=d)


def _crossing(motion: Motion, keys: dict[str, Any], frame: Frame) -> dict[str, Any] | None:
    """The crossing's keys if the motion is one (module docstring), else None."""
    speeds, pts = keys["speeds"], motion.follow.vertices
    if keys["start"] != "ego_ttc" or len(speeds) != 2 or speeds[0][1] != 0.0 or len(pts) != 3 or \
            motion.body.centre_x_m != 0.0 or motion.body.centre_y_m != 0.0:
        return None
    h = math.remainder(motion.init_h_rad - frame.pose.h_rad, 2 * math.pi)
    start, sync = _crd(frame, *pts[0]), _crd(frame, *pts[1])
    if math.dist(sync, keys["start_point"]) > MATCH_TOL:
        return None
    d = exact_distance(tuple(start), tuple(sync), h)
    accel, speed = speeds[1]
    if not 0.0 < accel <= d or speed <= 0.0:
        return None
    behaviour = crossing(tuple(start), h, d, speed, accel)
    if math.dist(behaviour.path.points[1], _crd(frame, *pts[2])) > 1e-6 or \
            abs(behaviour.trigger.ttc_s - keys["start_value"]) > MATCH_TOL:
        return None
    return {"x_m": sync[0], "y_m": sync[1], "heading_rad": h, "start_distance_m": d, "accel_distance_m": accel,
            "speed_mps": speed}
