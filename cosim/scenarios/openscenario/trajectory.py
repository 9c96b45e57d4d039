"""``<FollowTrajectoryAction>`` with a ``<Polyline>`` shape: an object's ``[objects.trajectory]``.

Read: ``<Trajectory closed="false">`` (1.0, or inside ``<TrajectoryRef>`` from 1.1) (its ``<ParameterDeclarations>`` empty) whose ``<Shape>`` is a
``<Polyline>`` of two or more ``<Vertex>`` with a world, road or lane ``<Position>`` and an optional
``time``; ``<TimeReference>`` ``<None/>`` (the entity moves at its own speed; vertex times have no
effect) or ``<Timing domainAbsoluteRelative scale offset>`` (every vertex needs its time; what crd
makes of them: :mod:`.trajectory_keys`); ``<TrajectoryFollowingMode followingMode="position">``;
``initialDistanceOffset`` 0. Refused with a one-line error: the ``<Clothoid>`` and ``<Nurbs>``
shapes, a closed trajectory, a trajectory from a catalogue, the ``follow`` mode.

The vertices are the entity's reference point; crd's trajectory moves the box's centre, so each
vertex moves by the box centre's offset turned to the heading of the segment that leaves it (the
last: that reaches it); exact on straight pieces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

from .opendrive import Road
from .positions import Pose, read_position
from .xml_source import Element, attr, child, children, choice, dispatch, fail, number, one_child, only, unsupported


@dataclass(frozen=True)
class Timing:
    """``<Timing>``: a vertex time ``tau`` is at ``offset + scale tau``, absolute or after the action's start."""

    absolute: bool
    scale: float
    offset_s: float
    elem: Element


@dataclass(frozen=True)
class FollowTrajectory:
    """The polyline's vertices (world x, y of the reference point), their positions, times and timing."""

    vertices: tuple[tuple[float, float], ...]
    elem: Element
    poses: tuple[Pose, ...] = ()
    times: tuple[float | None, ...] = ()
    timing: Timing | None = None


def _timing(elem: Element) -> Timing | None:
    kind = one_child(elem, ("None", "Timing"))
    only(kind, ())
    if kind.tag == "None":
        return None
    domain = choice(kind, "domainAbsoluteRelative", ("absolute", "relative"))
    scale = number(kind, "scale")
    if scale <= 0.0:
        raise fail(kind, f"scale: expected > 0, got {scale:g}")
    return Timing(domain == "absolute", scale, number(kind, "offset"), kind)


def _polyline(elem: Element, roads: Mapping[str, Road]) -> tuple[tuple[Pose, ...], tuple[float | None, ...]]:
    vertices = only(elem, ("Vertex",))
    if len(vertices) < 2:
        raise fail(elem, f"expected two or more <Vertex>, got {len(vertices)}")
    poses, times = [], []
    for v in vertices:
        only(v, ("Position",))
        times.append(number(v, "time") if v.get("time") is not None else None)
        poses.append(read_position(child(v, "Position"), roads))
    return tuple(poses), tuple(times)


def _curve(elem: Element, roads: Mapping[str, Road]) -> None:  # noqa: ARG001 - one handler signature
    raise unsupported(elem, "crd's trajectories are polylines (<Polyline>)")


SHAPES = {"Polyline": _polyline, "Clothoid": _curve, "Nurbs": _curve}


def _trajectory(elem: Element, roads: Mapping[str, Road]) -> tuple[tuple[Pose, ...], tuple[float | None, ...]]:
    only(elem, ("ParameterDeclarations", "Shape"))
    attr(elem, "name")
    if attr(elem, "closed", "false") != "false":
        raise unsupported(elem, "a closed trajectory: crd's objects stop at the path's end")
    params = child(elem, "ParameterDeclarations", False)
    if params is not None and children(params):
        raise unsupported(children(params)[0], "crd reads trajectories without parameters")
    return dispatch(one_child(child(elem, "Shape")), SHAPES, roads)


def read_follow_trajectory(elem: Element, roads: Mapping[str, Road]) -> FollowTrajectory:
    """One ``<FollowTrajectoryAction>``."""
    only(elem, ("Trajectory", "TrajectoryRef", "TimeReference", "TrajectoryFollowingMode"))
    if number(elem, "initialDistanceOffset", 0.0) != 0.0:
        raise unsupported(elem, "initialDistanceOffset: crd's objects start at the path's start")
    mode = child(elem, "TrajectoryFollowingMode", False)
    if mode is not None and attr(mode, "followingMode") != "position":
        raise unsupported(mode, "followingMode: crd's objects follow the path exactly (position)")
    timing = _timing(child(elem, "TimeReference"))
    ref = child(elem, "TrajectoryRef", False)
    trajectory = child(elem, "Trajectory") if ref is None else one_child(ref, ("Trajectory",))
    poses, times = _trajectory(trajectory, roads)
    if timing is not None and None in times:
        raise fail(trajectory, "a <Timing> reference needs a time on every <Vertex>")
    return FollowTrajectory(tuple((p.x_m, p.y_m) for p in poses), elem, poses, times, timing)


def centre_path(vertices: tuple[tuple[float, float], ...], cx_m: float, cy_m: float) -> list[tuple[float, float]]:
    """The box centre's path: each vertex moved by ``R(h) (cx, cy)``, ``h`` the heading of its segment."""
    out = []
    for i, (x, y) in enumerate(vertices):
        a, b = (vertices[i], vertices[i + 1]) if i + 1 < len(vertices) else (vertices[i - 1], vertices[i])
        h = math.atan2(b[1] - a[1], b[0] - a[0])
        out.append((x + cx_m * math.cos(h) - cy_m * math.sin(h), y + cx_m * math.sin(h) + cy_m * math.cos(h)))
    return out
