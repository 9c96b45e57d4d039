"""``<FollowTrajectoryAction>`` with a ``<Polyline>`` shape: an object's ``[objects.trajectory]``.

Read: ``<Trajectory closed="false">`` (1.0, or inside ``<TrajectoryRef>`` from 1.1) (its ``<ParameterDeclarations>`` empty) whose ``<Shape>`` is a
``<Polyline>`` of two or more ``<Vertex>`` with a world, road or lane ``<Position>`` (a vertex's
``time`` is read and has no effect: with ``<TimeReference><None/>`` OpenSCENARIO 1.x moves the
entity at its own speed); ``<TimeReference><None/>``; ``<TrajectoryFollowingMode
followingMode="position">``; ``initialDistanceOffset`` 0. Refused with a one-line error: the
``<Clothoid>`` and ``<Nurbs>`` shapes, a ``<Timing>`` reference, a closed trajectory, a trajectory
from a catalogue, the ``follow`` mode.

The vertices are the entity's reference point; crd's trajectory moves the box's centre, so each
vertex moves by the box centre's offset turned to the heading of the segment that leaves it (the
last: that reaches it); exact on straight pieces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

from .opendrive import Road
from .positions import read_position
from .xml_source import Element, attr, child, children, dispatch, fail, number, one_child, only, unsupported


@dataclass(frozen=True)
class FollowTrajectory:
    """The polyline's vertices (world x, y of the reference point)."""

    vertices: tuple[tuple[float, float], ...]
    elem: Element


def _no_timing(elem: Element) -> None:
    kind = one_child(elem)
    if kind.tag != "None":
        raise unsupported(kind, "a timing reference: crd's object moves at its own speed (<TimeReference><None/>)")


def _polyline(elem: Element, roads: Mapping[str, Road]) -> tuple[tuple[float, float], ...]:
    vertices = only(elem, ("Vertex",))
    if len(vertices) < 2:
        raise fail(elem, f"expected two or more <Vertex>, got {len(vertices)}")
    out = []
    for v in vertices:
        only(v, ("Position",))
        number(v, "time", 0.0)
        pose = read_position(child(v, "Position"), roads)
        out.append((pose.x_m, pose.y_m))
    return tuple(out)


def _curve(elem: Element, roads: Mapping[str, Road]) -> None:  # noqa: ARG001 - one handler signature
    raise unsupported(elem, "crd's trajectories are polylines (<Polyline>)")


SHAPES = {"Polyline": _polyline, "Clothoid": _curve, "Nurbs": _curve}


def _trajectory(elem: Element, roads: Mapping[str, Road]) -> tuple[tuple[float, float], ...]:
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
    _no_timing(child(elem, "TimeReference"))
    ref = child(elem, "TrajectoryRef", False)
    trajectory = child(elem, "Trajectory") if ref is None else one_child(ref, ("Trajectory",))
    return FollowTrajectory(_trajectory(trajectory, roads), elem)


def centre_path(vertices: tuple[tuple[float, float], ...], cx_m: float, cy_m: float) -> list[tuple[float, float]]:
    """The box centre's path: each vertex moved by ``R(h) (cx, cy)``, ``h`` the heading of its segment."""
    out = []
    for i, (x, y) in enumerate(vertices):
        a, b = (vertices[i], vertices[i + 1]) if i + 1 < len(vertices) else (vertices[i - 1], vertices[i])
        h = math.atan2(b[1] - a[1], b[0] - a[0])
        out.append((x + cx_m * math.cos(h) - cy_m * math.sin(h), y + cx_m * math.sin(h) + cy_m * math.cos(h)))
    return out
