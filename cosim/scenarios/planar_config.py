"""The scenario's planar tables: the road, object poses and motions in the plane, the driver's steering.

Declared like every key (:func:`ecu.settings.setting`) and used by :mod:`cosim.scenarios.config`.
Each table is optional, and unset means the 1-D world of today, so a scenario without them runs
(and resolves, ``config.resolved.toml``) exactly as before. World frame: x and y in metres, y to
the left of x, headings counter-clockwise from x (ISO 8855, OpenDRIVE); with the builtin plant the
ego's front bumper starts at x = 0 heading along x, so the world frame is the 1-D path frame.

* ``[road]``: ASAM OpenDRIVE 1.x's road model, a reference line (``<planView>``: lines, arcs and
  clothoids end to end from a start pose) and lane sections (``<laneSection>``, constant widths per
  lane, listed outward), built into :class:`cosim.world.road.Road`;
* ``[objects.pose]``, ``[objects.road_pose]``: where an object stands (its box's centre), in world or
  road coordinates (OpenSCENARIO's WorldPosition and RoadPosition);
* ``[objects.trajectory]``: waypoints or a lane, a speed profile and a start trigger
  (:mod:`cosim.world.trajectory`); ``[objects.crossing]``: Euro NCAP's crossing target
  (:func:`cosim.world.trajectory.crossing`);
* ``[driver.steering]``: who turns the wheel (:mod:`cosim.world.steering_models`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ecu.settings import Range, SettingError, setting

#: OpenDRIVE geometry kinds of a ``[[road.geometry]]`` entry
GEOMETRY_KINDS = ("line", "arc", "spiral")
#: what an object's ``[objects.trajectory]`` start waits for (cosim.world.trajectory.TRIGGERS, plus at t = 0)
START_KINDS = ("at_start", "time", "ego_ttc", "ego_distance")
_WIDE = Range(-1e5, 1e5)
_ANGLE = Range(-2.0 * math.pi, 2.0 * math.pi)
_CURVATURE = Range(-1.0, 1.0)


def _check_points(points: tuple[tuple[float, ...], ...], name: str) -> None:
    """Every row a pair ``[a, b]``."""
    for i, row in enumerate(points):
        if len(row) != 2:
            raise SettingError(f"{name}[{i}]", f"expected a pair [a, b], got {list(row)}")


@dataclass(frozen=True)
class RoadGeometryConfig:
    """One ``[[road.geometry]]`` entry: an OpenDRIVE ``<geometry>`` record, placed where the previous one ends."""

    kind: str = setting(allowed=GEOMETRY_KINDS, doc="line, arc (constant curvature) or spiral (clothoid)")
    length_m: float = setting(unit="m", allowed=Range(0.0, 1e5, low_open=True), doc="length along the reference line")
    curvature_1pm: float | None = setting(None, unit="1/m", allowed=_CURVATURE,
                                          doc="arc: curvature, positive to the left (1/radius)")
    curvature_start_1pm: float | None = setting(None, unit="1/m", allowed=_CURVATURE, doc="spiral: curvature at its start")
    curvature_end_1pm: float | None = setting(None, unit="1/m", allowed=_CURVATURE, doc="spiral: curvature at its end")

    def __post_init__(self) -> None:
        needs = {"line": (), "arc": ("curvature_1pm",), "spiral": ("curvature_start_1pm", "curvature_end_1pm")}
        for name in ("curvature_1pm", "curvature_start_1pm", "curvature_end_1pm"):
            given = getattr(self, name) is not None
            if given != (name in needs[self.kind]):
                problem = "missing" if not given else "not used by this kind"
                raise SettingError(name, f"{problem}; a {self.kind} takes {list(needs[self.kind]) or 'no curvature'}")
        if self.kind == "arc" and self.curvature_1pm == 0.0:
            raise SettingError("curvature_1pm", "expected a non-zero curvature (a straight piece is a line)")


@dataclass(frozen=True)
class LaneSectionConfig:
    """One ``[[road.lane_sections]]`` entry: OpenDRIVE's ``<laneSection s>`` with lanes of constant width."""

    s_m: float = setting(0.0, unit="m", allowed=Range(0.0, 1e5), doc="where along the reference line it starts")
    left_m: tuple[float, ...] = setting((3.5,), unit="m", allowed=Range(0.0, 20.0, low_open=True),
                                        doc="widths of the lanes left of the reference line, ids 1, 2, ... outward")
    right_m: tuple[float, ...] = setting((3.5,), unit="m", allowed=Range(0.0, 20.0, low_open=True),
                                         doc="widths of the lanes right of the reference line, ids -1, -2, ... outward")


@dataclass(frozen=True)
class RoadConfig:
    """``[road]``: a road as OpenDRIVE draws one: a reference line and lanes beside it.

    The reference line starts at (``x_m``, ``y_m``) heading ``heading_rad`` and runs through the
    ``[[road.geometry]]`` pieces end to end; the lanes of ``[[road.lane_sections]]`` lie to its left
    (ids 1, 2, ...) and right (-1, -2, ...). Right-hand traffic drives in the right lanes: with the
    ego on y = 0 in lane -1 of 3.5 m, the reference line is at y = 1.75. The road guides the
    path-following driver (``[driver.steering] lane``), places objects (``[objects.road_pose]``) and is
    drawn in the bird's-eye view; it does not bound the motion (leaving it is not detected yet).
    """

    x_m: float = setting(0.0, unit="m", allowed=_WIDE, doc="start of the reference line")
    y_m: float = setting(0.0, unit="m", allowed=_WIDE, doc="start of the reference line")
    heading_rad: float = setting(0.0, unit="rad", allowed=_ANGLE, doc="heading of the reference line at its start")
    geometry: tuple[RoadGeometryConfig, ...] = setting((), doc="the reference line's pieces in order (at least one)")
    lane_sections: tuple[LaneSectionConfig, ...] = setting(
        (LaneSectionConfig(),), doc="lane sections by increasing s_m, the first at 0 (default: one lane each side)")

    def __post_init__(self) -> None:
        if not self.geometry:
            raise SettingError("geometry", "expected at least one [[road.geometry]] piece, got none")
        starts = [sec.s_m for sec in self.lane_sections]
        if not starts or starts[0] != 0.0 or any(b <= a for a, b in zip(starts, starts[1:])):
            raise SettingError("lane_sections", f"expected s_m increasing from 0, got {starts}")


@dataclass(frozen=True)
class PoseConfig:
    """``[objects.pose]``: the object's box centre and heading at t = 0, in world coordinates."""

    x_m: float = setting(unit="m", allowed=_WIDE, doc="centre of the object's box")
    y_m: float = setting(unit="m", allowed=_WIDE, doc="centre of the object's box, left positive")
    heading_rad: float = setting(0.0, unit="rad", allowed=_ANGLE, doc="the box's (and the motion's) direction")


@dataclass(frozen=True)
class RoadPoseConfig:
    """``[objects.road_pose]``: the object's box centre in road coordinates (needs ``[road]``)."""

    s_m: float = setting(unit="m", allowed=Range(0.0, 1e5), doc="along the reference line")
    t_m: float = setting(0.0, unit="m", allowed=Range(-100.0, 100.0), doc="across it, left positive")
    heading_rad: float = setting(0.0, unit="rad", allowed=_ANGLE, doc="relative to the road's heading at s_m")


@dataclass(frozen=True)
class TrajectoryConfig:
    """``[objects.trajectory]``: a path, a speed profile along it, and what starts the motion.

    The path is ``waypoints`` (straight segments) or the line ``lane_offset_m`` from the centre of
    ``lane`` of ``[road]`` from ``start_s_m`` on; the object's box centre follows it, heading along
    it. ``speeds`` are ``[at, speed_mps]`` knots over path length (constant acceleration between
    knots: "5 km/h after 1 m") or over time since the start; after the last knot the speed stays.
    Until it starts the object stands at the path's start. Start: at t = 0, at ``start_value`` s, or
    when the ego's front bumper is ``start_value`` s (``ego_ttc``: at its speed) or m
    (``ego_distance``) from ``start_point`` along its heading: Euro NCAP's synchronisation of targets.
    """

    waypoints: tuple[tuple[float, float], ...] = setting((), unit="m", allowed=_WIDE,
                                                         doc="[x, y] points of the path in order")
    lane: int | None = setting(None, allowed=Range(-20, 20), doc="... or the centre of this lane of [road]")
    lane_offset_m: float = setting(0.0, unit="m", allowed=Range(-20.0, 20.0), doc="lane: offset from its centre, left positive")
    start_s_m: float = setting(0.0, unit="m", allowed=Range(0.0, 1e5), doc="lane: where along the road the path starts")
    speeds: tuple[tuple[float, float], ...] = setting((), doc="[at, speed_mps] knots, at increasing from >= 0")
    speeds_over: str = setting("distance", allowed=("distance", "time"), doc="the knots' abscissa: path length (m) or time (s)")
    start: str = setting("at_start", allowed=START_KINDS, doc="what starts the motion (see above)")
    start_value: float = setting(0.0, allowed=Range(0.0, 1e5), doc="time (s), ego time to the point (s) or distance (m)")
    start_point: tuple[float, ...] = setting((), unit="m", allowed=_WIDE, doc="ego_ttc, ego_distance: the point [x, y]")

    def __post_init__(self) -> None:
        _check_points(self.waypoints, "waypoints")
        _check_points(self.speeds, "speeds")
        if (len(self.waypoints) >= 2) == (self.lane is not None):
            raise SettingError("waypoints", "expected either two or more waypoints or a lane, got "
                                            f"{len(self.waypoints)} waypoint(s) and lane {self.lane}")
        if self.start in ("ego_ttc", "ego_distance") and len(self.start_point) != 2:
            raise SettingError("start_point", f"expected [x, y] for start = {self.start!r}, got {list(self.start_point)}")
        if not self.speeds:
            raise SettingError("speeds", "expected at least one [at, speed_mps] knot")


@dataclass(frozen=True)
class CrossingConfig:
    """``[objects.crossing]``: a target crossing the ego's path, Euro NCAP style.

    It starts ``start_distance_m`` before the synchronisation point (``x_m``, ``y_m``) and walks or
    rides straight through it along ``heading_rad``: from rest, ``speed_mps`` reached after
    ``accel_distance_m`` of constant acceleration, then held. It starts when the ego's time to the
    point (its front bumper's distance to it along its heading, over its speed) equals the target's
    own time to it, so both arrive together: with the point on the ego's path the target meets the
    middle of the ego's front, the 50 % impact location. Euro NCAP CPNA (adult from the near side):
    5 km/h after 1.0 m, 4.0 m from the 50 % impact point (planar-protocol-facts.md §1.3-1.4).
    """

    x_m: float = setting(unit="m", allowed=_WIDE, doc="the synchronisation point, on the ego's path")
    y_m: float = setting(unit="m", allowed=_WIDE, doc="the synchronisation point")
    heading_rad: float = setting(math.pi / 2, unit="rad", allowed=_ANGLE,
                                 doc="the direction it crosses in (pi/2: toward +y, from the right of an ego along +x)")
    start_distance_m: float = setting(4.0, unit="m", allowed=Range(0.0, 1e3, low_open=True),
                                      doc="from its start to the point (CPNA: 4.0)")
    accel_distance_m: float = setting(1.0, unit="m", allowed=Range(0.0, 1e3, low_open=True),
                                      doc="accelerating from rest over this (CPNA: 1.0)")
    speed_mps: float = setting(5.0 / 3.6, unit="m/s", allowed=Range(0.0, 40.0, low_open=True),
                               doc="steady speed (CPNA: 5 km/h)")

    def __post_init__(self) -> None:
        if self.accel_distance_m > self.start_distance_m:
            raise SettingError("accel_distance_m", f"expected at most start_distance_m ({self.start_distance_m}),"
                                                   f" got {self.accel_distance_m}")


@dataclass(frozen=True)
class LaneChangeConfig:
    """One ``[[driver.steering.lane_changes]]`` entry: move to ``to_lane`` at a time or a station."""

    to_lane: int = setting(allowed=Range(-20, 20), doc="the lane of [road] to move to")
    at_time_s: float | None = setting(None, unit="s", allowed=Range(0.0, 3600.0), doc="start at this time")
    at_station_m: float | None = setting(None, unit="m", allowed=Range(0.0, 1e5),
                                         doc="... or once the ego's front bumper reaches this s along the road")
    length_m: float = setting(50.0, unit="m", allowed=Range(1.0, 1e4),
                              doc="distance along the road over which the path moves across (sinusoidal)")

    def __post_init__(self) -> None:
        if (self.at_time_s is None) == (self.at_station_m is None):
            raise SettingError("at_time_s", "expected exactly one of at_time_s and at_station_m")


@dataclass(frozen=True)
class SteeringConfig:
    """``[driver.steering]``: who turns the wheel (absent: the wheel is held straight).

    ``held`` holds the steering wheel at ``angle_rad``. ``path_following`` steers with pure pursuit
    (:mod:`cosim.world.path_following`) along the centre of ``lane`` of ``[road]`` or along
    ``waypoints``, and changes lanes as ``lane_changes`` say. Its vehicle geometry (wheelbase, CG to
    rear axle, steering ratio, road-wheel angle limit) is the builtin plant's, with
    ``[plant.parameters]`` applied; a third-party FMU gives them here.
    """

    model: str = setting("path_following", allowed=("held", "path_following"), doc="the steering model")
    angle_rad: float = setting(0.0, unit="rad", allowed=Range(-20.0, 20.0),
                               doc="held: the steering-wheel angle, positive left")
    lane: int | None = setting(None, allowed=Range(-20, 20), doc="path_following: follow this lane's centre")
    waypoints: tuple[tuple[float, float], ...] = setting((), unit="m", allowed=_WIDE,
                                                         doc="path_following: ... or these [x, y] points")
    lane_changes: tuple[LaneChangeConfig, ...] = setting((), doc="path_following with a lane: lane changes in order")
    lookahead_time_s: float = setting(1.0, unit="s", allowed=Range(0.05, 5.0),
                                      doc="pure pursuit: look-ahead as time of travel (1 s: drivers steer by the "
                                          "road about 1 s ahead, Land & Horwood, Nature 377, 1995)")
    lookahead_min_m: float = setting(3.0, unit="m", allowed=Range(0.5, 100.0), doc="pure pursuit: shortest look-ahead")
    lookahead_max_m: float = setting(40.0, unit="m", allowed=Range(0.5, 500.0), doc="pure pursuit: longest look-ahead")
    wheelbase_m: float | None = setting(None, unit="m", allowed=Range(0.5, 20.0), doc="unset: the builtin plant's")
    cg_to_rear_axle_m: float | None = setting(None, unit="m", allowed=Range(0.0, 20.0), doc="unset: the builtin plant's")
    steering_ratio: float | None = setting(None, allowed=Range(1.0, 50.0), doc="unset: the builtin plant's")
    max_road_wheel_angle_rad: float | None = setting(None, unit="rad", allowed=Range(0.01, 1.5),
                                                     doc="unset: the builtin plant's")

    def __post_init__(self) -> None:
        _check_points(self.waypoints, "waypoints")
        if self.model != "path_following":
            return
        if (self.lane is not None) == (len(self.waypoints) >= 2):
            raise SettingError("lane", "path_following: expected either a lane or two or more waypoints")
        if self.lane_changes and self.lane is None:
            raise SettingError("lane_changes", "expected a lane to change from (lane = ...)")
