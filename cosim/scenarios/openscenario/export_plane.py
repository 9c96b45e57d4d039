"""The planar parts of a crd scenario as OpenDRIVE and OpenSCENARIO elements, built with ``scenariogeneration``.

The inverse of the import's planar mapping (:mod:`.planar_road`, :mod:`.placement`,
:mod:`.trajectory_keys`), written so that reading the files back gives the same scenario bit for bit.
crd's world frame is the file's (the ego's front bumper at the origin, heading along x), so every
number is written as crd holds it:

* ``[road]``: one road, its ``<planView>`` starting at ``(x_m, y_m, heading_rad)`` with one
  ``<line>``, ``<arc>`` or ``<spiral>`` per ``[[road.geometry]]`` piece (scenariogeneration places
  each record where the previous one ends), and one lane section of constant widths;
* an object placed in the plane has its reference point at its box centre, where crd places it:
  ``road_pose`` -> ``<RoadPosition s t>`` with a relative ``<Orientation h>``, ``pose`` ->
  ``<RelativeObjectPosition entityRef=ego dx dy>`` with a relative ``<Orientation h>`` (the ego's
  reference point is the origin, heading along x; a ``<WorldPosition>`` on the ego's axis would read
  back as ``position_m`` and ``lateral_m``, the relative position as the pose at any heading);
* a trajectory -> ``<FollowTrajectoryAction>`` with a ``<Polyline>`` (``TimeReference`` none,
  following mode position): waypoints as world positions; a lane path as lane positions of that
  lane and offset from ``start_s_m`` to the road's end, close enough on curved pieces that the
  chords stay within :data:`CHORD_SAGITTA_M` of the lane (crd reads such a polyline back as the
  lane). Each vertex carries the time the object reaches it (none if it stops before the last).
  Started at t = 0: an Init action; at a time: a story event on ``SimulationTimeCondition``; by
  ``ego_ttc``: on the ego's ``TimeToCollisionCondition`` to ``start_point`` (``freespace``). Speeds
  that change: linear ``SpeedAction`` segments (:mod:`.speed_segments`), at ``s = 0`` in the
  trajectory's event, later started by the object's ``TraveledDistanceCondition``;
* a crossing -> the object at its start, speed 0, and one event started by the ego's
  ``TimeToCollisionCondition`` to the synchronisation point (``freespace``: crd's time of the front
  bumper to the point): a polyline start -> point -> end and a linear ``SpeedAction`` to its speed
  over its acceleration distance.
"""

from __future__ import annotations

import math

from scenariogeneration import xodr, xosc

from ...world.road import Road
from ...world.scene_build import lane_centre_t
from ...world.targets import TARGET_CLASSES
from ...world.trajectory import SpeedProfile, crossing
from ..config import ObjectConfig
from ..planar_config import CrossingConfig, RoadConfig, TrajectoryConfig
from .speed_segments import Segment, knots, segments

ROAD_ID = 0
#: how far the chords of an exported lane path may leave the lane (m): the sagitta c^2 |k| / 8
CHORD_SAGITTA_M = 0.01
#: a target class's radar size class -> the OpenSCENARIO vehicle category (pedestrians are <Pedestrian>)
VEHICLE_CATEGORIES = {"bicycle": xosc.VehicleCategory.bicycle, "motorcycle": xosc.VehicleCategory.motorbike,
                      "car": xosc.VehicleCategory.car}
_GEOMETRIES = {
    "line": lambda g: xodr.Line(g.length_m),
    "arc": lambda g: xodr.Arc(g.curvature_1pm, length=g.length_m),
    "spiral": lambda g: xodr.Spiral(g.curvature_start_1pm, g.curvature_end_1pm, length=g.length_m),
}


class PlaneExportError(ValueError):
    """A planar scenario that the OpenSCENARIO subset cannot carry exactly."""


def opendrive_road(cfg: RoadConfig, name: str) -> xodr.OpenDrive:
    """``[road]`` as an OpenDRIVE file of one road (id :data:`ROAD_ID`)."""
    if len(cfg.lane_sections) != 1:
        raise PlaneExportError(f"[road] with {len(cfg.lane_sections)} lane sections: the export writes one")
    if math.remainder(cfg.heading_rad, 2 * math.pi) != cfg.heading_rad:
        raise PlaneExportError(f"road.heading_rad = {cfg.heading_rad}: outside (-pi, pi], the file's heading "
                               "would read back as another number")
    plan = xodr.PlanView(cfg.x_m, cfg.y_m, cfg.heading_rad)
    for g in cfg.geometry:
        plan.add_geometry(_GEOMETRIES[g.kind](g))
    section = xodr.LaneSection(0, xodr.standard_lane())
    for width in cfg.lane_sections[0].left_m:
        section.add_left_lane(xodr.Lane(a=width))
    for width in cfg.lane_sections[0].right_m:
        section.add_right_lane(xodr.Lane(a=width))
    lanes = xodr.Lanes()
    lanes.add_lanesection(section)
    odr = xodr.OpenDrive(name)
    odr.add_road(xodr.Road(ROAD_ID, plan, lanes))
    odr.adjust_roads_and_lanes()
    return odr


def category(obj: ObjectConfig, bicycle_max_width_m: float) -> tuple[str, xosc.VehicleCategory | None]:
    """("Pedestrian", None) or ("Vehicle", category): from the target class, else from the width."""
    target = TARGET_CLASSES.get(obj.target_class or "")
    if target is not None and target.size_class == "pedestrian":
        return "Pedestrian", None
    if target is not None:
        return "Vehicle", VEHICLE_CATEGORIES[target.size_class]
    return "Vehicle", xosc.VehicleCategory.bicycle if obj.width_m <= bicycle_max_width_m else xosc.VehicleCategory.car


def in_plane(obj: ObjectConfig) -> bool:
    """Placed or moved by a planar table (its reference point is then its box centre)."""
    return any(v is not None for v in (obj.pose, obj.road_pose, obj.trajectory, obj.crossing))


def _step(speed_mps: float) -> xosc.AbsoluteSpeedAction:
    return xosc.AbsoluteSpeedAction(speed_mps, xosc.TransitionDynamics(xosc.DynamicsShapes.step,
                                                                       xosc.DynamicsDimension.time, 0.0))


def placed_init(obj: ObjectConfig, ego: str) -> list:
    """The Init actions of an object placed by ``pose`` or ``road_pose``: teleport and speed."""
    moving = obj.brake_decel_mps2 > 0.0 or obj.lateral_end_m is not None
    if moving or obj.speed_mps < 0.0:
        raise PlaneExportError(f"object {obj.name!r}: braking, lateral motion or a negative speed of an object "
                               "placed in the plane: the export writes a constant forward speed")
    if obj.road_pose is not None:
        rp = obj.road_pose
        orient = xosc.Orientation(h=rp.heading_rad, reference=xosc.ReferenceContext.relative)
        where = xosc.RoadPosition(rp.s_m, rp.t_m, ROAD_ID, orient)
    else:
        p = obj.pose
        if math.remainder(p.heading_rad, 2 * math.pi) != p.heading_rad:
            raise PlaneExportError(f"object {obj.name!r}: pose.heading_rad = {p.heading_rad}: outside (-pi, pi] it "
                                   "reads back as another number")
        orient = xosc.Orientation(h=p.heading_rad, reference=xosc.ReferenceContext.relative)
        where = xosc.RelativeObjectPosition(ego, p.x_m, p.y_m, orientation=orient)
    return [xosc.TeleportAction(where), _step(obj.speed_mps)]


def _knots(obj: ObjectConfig, cfg: TrajectoryConfig) -> list[Segment]:
    """The speed segments of the trajectory's knots (:mod:`.speed_segments`), if they read back as the same knots."""
    knotted = [list(k) for k in cfg.speeds]
    if cfg.speeds_over != "distance" or knotted[0][0] != 0.0:
        raise PlaneExportError(f"object {obj.name!r}: trajectory speeds {knotted} over {cfg.speeds_over}: the export "
                               "writes knots over distance from [0.0, v]")
    segs = segments(knotted)
    if knots(knotted[0][1], segs) != knotted:
        raise PlaneExportError(f"object {obj.name!r}: trajectory speeds {knotted}: as SpeedAction segments they read "
                               f"back as {knots(knotted[0][1], segs)}")
    if cfg.start != "at_start" and knotted[0][1] > 0.0 and any(seg.start_m > 0.0 for seg in segs):
        raise PlaneExportError(f"object {obj.name!r}: trajectory speeds {knotted} from a first speed > 0, started "
                               f"{cfg.start!r}: a TraveledDistanceCondition would count the way before the start")
    return segs


def _lane_stations(road: Road, cfg: TrajectoryConfig, t_m: float) -> list[float]:
    """Stations from ``start_s_m`` to the road's end: the joints, and on curved pieces close enough that the
    chords' sagitta on the path at offset ``t``, ``(1 - k t) ds^2 |k| / 8``, stays within :data:`CHORD_SAGITTA_M`."""
    plan, stations = road.plan, [cfg.start_s_m]
    for p in plan.placed:
        end = p.s_m + p.segment.length_m
        if end <= cfg.start_s_m:
            continue
        k = max(abs(p.segment.curvature_at(0.0)), abs(p.segment.curvature_at(p.segment.length_m)))
        step = math.sqrt(8.0 * CHORD_SAGITTA_M / (k * (1.0 + k * abs(t_m)))) if k > 0.0 else math.inf
        n = max(1, math.ceil((end - stations[-1]) / step))
        start = stations[-1]
        stations.extend(start + (end - start) * i / n for i in range(1, n + 1))
    return stations


def _vertices(obj: ObjectConfig, road: Road | None) -> tuple[list, list[tuple[float, float]]]:
    """The polyline's positions and their world points."""
    cfg = obj.trajectory
    if cfg.lane is None:
        return [xosc.WorldPosition(x, y) for x, y in cfg.waypoints], [tuple(p) for p in cfg.waypoints]
    t = lane_centre_t(road, cfg.lane, cfg.start_s_m) + cfg.lane_offset_m
    stations = _lane_stations(road, cfg, t)
    points = [road.pose_at(s, t)[:2] for s in stations]
    return [xosc.LanePosition(s, cfg.lane_offset_m, cfg.lane, ROAD_ID) for s in stations], points


def _times(points: list[tuple[float, float]], profile: SpeedProfile) -> list[float]:
    """When the object reaches each vertex (none, if it stops before the last)."""
    out, d = [0.0], 0.0
    for a, b in zip(points, points[1:]):
        d += math.hypot(b[0] - a[0], b[1] - a[1])
        out.append(profile.time_to_reach(d))
    return out if math.isfinite(out[-1]) else []


def _follow(name: str, positions: list, times: list[float]) -> xosc.FollowTrajectoryAction:
    trajectory = xosc.Trajectory(f"{name}_path", False)
    trajectory.add_shape(xosc.Polyline(times, positions))
    return xosc.FollowTrajectoryAction(trajectory, xosc.FollowingMode.position)


def _ttc_start(cfg: TrajectoryConfig, ego: str) -> xosc.EntityTrigger:
    cond = xosc.TimeToCollisionCondition(cfg.start_value, xosc.Rule.lessOrEqual, alongroute=False, freespace=True,
                                         position=xosc.WorldPosition(*cfg.start_point))
    return xosc.EntityTrigger("trajectory_ttc", 0.0, xosc.ConditionEdge.none, cond, ego)


def _time_start(cfg: TrajectoryConfig, ego: str) -> xosc.ValueTrigger:  # noqa: ARG001 - one signature
    return xosc.ValueTrigger("trajectory_time", 0.0, xosc.ConditionEdge.none,
                             xosc.SimulationTimeCondition(cfg.start_value, xosc.Rule.greaterOrEqual))


#: a trajectory's ``start`` (other than at_start: an Init action) -> its event's trigger
STARTS = {"time": _time_start, "ego_ttc": _ttc_start}


def _speed_events(obj: ObjectConfig, segs: list[Segment], with_path: xosc.Event | None) -> list[xosc.Event]:
    """Each segment as a linear SpeedAction over its distance; at s = 0 in ``with_path`` (the trajectory's event),
    else an event started by the object's TraveledDistanceCondition."""
    events = []
    for i, seg in enumerate(segs):
        dyn = xosc.TransitionDynamics(xosc.DynamicsShapes.linear, xosc.DynamicsDimension.distance, seg.length_m)
        action = xosc.AbsoluteSpeedAction(seg.target_mps, dyn)
        if seg.start_m == 0.0 and with_path is not None:
            with_path.add_action("speed", action)
            continue
        event = xosc.Event(f"{obj.name}_speed_{i}", xosc.Priority.parallel)
        event.add_action("speed", action)
        event.add_trigger(xosc.EntityTrigger(f"speed_{i}_distance", 0.0, xosc.ConditionEdge.none,
                                             xosc.TraveledDistanceCondition(seg.start_m), obj.name))
        events.append(event)
    return events


def trajectory_actions(obj: ObjectConfig, road: Road | None, ego: str) -> tuple[list, list[xosc.Event]]:
    """(Init actions, story events) of an object with ``[objects.trajectory]``."""
    cfg = obj.trajectory
    segs = _knots(obj, cfg)
    positions, points = _vertices(obj, road)
    first = positions[0] if cfg.lane is not None else xosc.WorldPosition(*points[0], 0.0, math.atan2(
        points[1][1] - points[0][1], points[1][0] - points[0][0]))
    follow = _follow(obj.name, positions, _times(points, SpeedProfile.over_distance(cfg.speeds)))
    init = [xosc.TeleportAction(first), _step(cfg.speeds[0][1])]
    if cfg.start == "at_start":
        return init + [follow], _speed_events(obj, segs, None)
    if cfg.start not in STARTS:
        raise PlaneExportError(f"object {obj.name!r}: trajectory start {cfg.start!r}: the export writes a start at "
                               f"t = 0 or by {', '.join(STARTS)}")
    event = xosc.Event(f"{obj.name}_trajectory", xosc.Priority.parallel)
    event.add_action("trajectory", follow)
    event.add_trigger(STARTS[cfg.start](cfg, ego))
    return init, [event] + _speed_events(obj, segs, event)


def crossing_actions(obj: ObjectConfig, ego: str) -> tuple[list, xosc.Event]:
    """(Init actions, story event) of an object with ``[objects.crossing]`` (see the module docstring)."""
    c: CrossingConfig = obj.crossing
    if math.remainder(c.heading_rad, 2 * math.pi) != c.heading_rad:
        raise PlaneExportError(f"object {obj.name!r}: crossing.heading_rad = {c.heading_rad} is outside (-pi, pi]")
    start = (c.x_m - c.start_distance_m * math.cos(c.heading_rad), c.y_m - c.start_distance_m * math.sin(c.heading_rad))
    behaviour = crossing(start, c.heading_rad, c.start_distance_m, c.speed_mps, c.accel_distance_m)
    end = behaviour.path.points[1]
    points = [start, (c.x_m, c.y_m), end]
    profile = SpeedProfile.over_distance([(0.0, 0.0), (c.accel_distance_m, c.speed_mps)])
    dist = [0.0, c.start_distance_m, behaviour.path.length_m]
    follow = _follow(obj.name, [xosc.WorldPosition(x, y, 0.0, c.heading_rad) for x, y in points],
                     [profile.time_to_reach(d) for d in dist])
    speed = xosc.AbsoluteSpeedAction(c.speed_mps, xosc.TransitionDynamics(
        xosc.DynamicsShapes.linear, xosc.DynamicsDimension.distance, c.accel_distance_m))
    event = xosc.Event(f"{obj.name}_crossing", xosc.Priority.parallel)
    event.add_action("path", follow)
    event.add_action("speed", speed)
    sync = xosc.WorldPosition(c.x_m, c.y_m, 0.0, c.heading_rad)
    cond = xosc.TimeToCollisionCondition(behaviour.trigger.ttc_s, xosc.Rule.lessOrEqual, alongroute=False,
                                         freespace=True, position=sync)
    event.add_trigger(xosc.EntityTrigger("crossing_ttc", 0.0, xosc.ConditionEdge.none, cond, ego))
    init = [xosc.TeleportAction(xosc.WorldPosition(*start, 0.0, c.heading_rad)), _step(0.0)]
    return init, event


def plane_actions(obj: ObjectConfig, road: Road | None, ego: str) -> tuple[list, list[xosc.Event]]:
    """(Init actions, story events) of an object placed or moved in the plane."""
    if obj.trajectory is not None:
        return trajectory_actions(obj, road, ego)
    if obj.crossing is not None:
        init, event = crossing_actions(obj, ego)
        return init, [event]
    return placed_init(obj, ego), []
