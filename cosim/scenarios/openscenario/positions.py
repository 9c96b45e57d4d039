"""``<Position>`` to a world pose ``(x, y, h)``: world, road and lane positions.

* ``<WorldPosition x y z h p r>``: ``z`` is read and has no effect (crd's world
  is level); ``p`` and ``r`` must be 0.
* ``<RoadPosition roadId s t>`` and ``<LanePosition roadId laneId s offset>``:
  through the road's reference line (:meth:`~.opendrive.Road.point`; the heading there); a lane
  position is at the lane's centre plus ``offset`` (left positive). Heading:
  an ``<Orientation type="absolute">`` gives it, ``type="relative"`` adds its
  ``h`` to the reference line's heading; without one, the heading is the lane's
  driving direction under right-hand traffic (lanes right of the centre lane
  along the reference line, those left of it against it).

* ``<RelativeObjectPosition entityRef dx dy>``, in an object's Init teleport only: ``(dx, dy)`` in
  the frame of the entity's reference point at its own Init position (which must be absolute), the
  heading that entity's plus the ``<Orientation>``'s ``h`` (``type="absolute"``: ``h`` itself);
  ``dz`` is read and has no effect. Read first as a :class:`Relative` (its pose unknown), then
  placed by :func:`resolve`. crd reads such an object as placed in the plane (``pose``,
  :mod:`.placement`): the export writes ``pose`` this way, so a box on the ego's axis stays a pose.

A road or lane position also keeps where it is on the road (:class:`RoadSpot`): when the road is
the scenario's ``[road]``, an object placed there becomes crd's ``road_pose`` (:mod:`.placement`).

Other position types (relative world, road and lane, route, trajectory, geographic) are not supported yet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

from .opendrive import Road
from .xml_source import Element, attr, child, choice, dispatch, fail, number, one_child, only, unsupported


@dataclass(frozen=True)
class RoadSpot:
    """A position in road coordinates: ``s``, ``t`` (from the reference line, left positive), the heading
    relative to the reference line's there, and for a lane position its lane and offset."""

    road_id: str
    s_m: float
    t_m: float
    h_rel_rad: float
    lane: int | None = None
    offset_m: float = 0.0


@dataclass(frozen=True)
class Relative:
    """A ``<RelativeObjectPosition>``: ``(dx, dy)`` in ``entity``'s frame, heading ``h`` relative to it (or absolute)."""

    entity: str
    dx_m: float
    dy_m: float
    h_rad: float
    absolute: bool
    elem: Element


@dataclass(frozen=True)
class Pose:
    """A reference point in world coordinates and its heading (and where it is on a road, or relative to which
    entity, if given so). A relative pose not yet :func:`resolve`-d has NaN coordinates."""

    x_m: float
    y_m: float
    h_rad: float
    spot: RoadSpot | None = None
    relative: Relative | None = None


def _no_tilt(elem: Element) -> None:
    for name in ("p", "r"):
        if number(elem, name, 0.0) != 0.0:
            raise unsupported(elem, f"{name}={elem.get(name)}: crd's world is level")


def _world(elem: Element, roads: Mapping[str, Road]) -> Pose:  # noqa: ARG001 - one handler signature
    _no_tilt(elem)
    number(elem, "z", 0.0)
    return Pose(number(elem, "x"), number(elem, "y"), number(elem, "h", 0.0))


def _road_of(elem: Element, roads: Mapping[str, Road]) -> Road:
    road_id = attr(elem, "roadId")
    if road_id not in roads:
        raise fail(elem, f"road {road_id!r} is not in the RoadNetwork's OpenDRIVE file (roads: {sorted(roads)})")
    return roads[road_id]


def _heading(elem: Element, road_hdg_rad: float, default_rel_rad: float) -> tuple[float, float]:
    """(world heading, heading relative to the reference line) of a road or lane position."""
    only(elem, ("Orientation",))
    orient = child(elem, "Orientation", False)
    if orient is None:
        return road_hdg_rad + default_rel_rad, default_rel_rad
    _no_tilt(orient)
    kind = attr(orient, "type", "relative")
    if kind not in ("relative", "absolute"):
        raise fail(orient, f"type: expected relative or absolute, got {kind!r}")
    h = number(orient, "h", 0.0)
    if kind == "absolute":
        return h, math.remainder(h - road_hdg_rad, 2 * math.pi)
    return road_hdg_rad + h, h


def _road_position(elem: Element, roads: Mapping[str, Road]) -> Pose:
    road = _road_of(elem, roads)
    s_m, t_m = number(elem, "s"), number(elem, "t")
    x, y = road.point(s_m, t_m)
    h, rel = _heading(elem, road.heading_at(s_m), 0.0)
    return Pose(x, y, h, RoadSpot(road.road_id, s_m, t_m, rel))


def _lane_position(elem: Element, roads: Mapping[str, Road]) -> Pose:
    road = _road_of(elem, roads)
    lane = int(number(elem, "laneId"))
    if lane not in road.lane_centre_t_m:
        raise fail(elem, f"lane {lane} is not on road {road.road_id!r} (lanes: {sorted(road.lane_centre_t_m)})")
    s_m, offset = number(elem, "s"), number(elem, "offset", 0.0)
    t_m = road.lane_centre_t_m[lane] + offset
    x, y = road.point(s_m, t_m)
    h, rel = _heading(elem, road.heading_at(s_m), 0.0 if lane < 0 else math.pi)
    return Pose(x, y, h, RoadSpot(road.road_id, s_m, t_m, rel, lane, offset))


def _relative_object(elem: Element, roads: Mapping[str, Road]) -> Pose:  # noqa: ARG001 - one handler signature
    only(elem, ("Orientation",))
    number(elem, "dz", 0.0)
    orient = child(elem, "Orientation", False)
    h, absolute = 0.0, False
    if orient is not None:
        _no_tilt(orient)
        absolute = choice(orient, "type", ("relative", "absolute"), "relative") == "absolute"
        h = number(orient, "h", 0.0)
    rel = Relative(attr(elem, "entityRef"), number(elem, "dx"), number(elem, "dy"), h, absolute, elem)
    return Pose(math.nan, math.nan, math.nan, relative=rel)


POSITIONS = {"WorldPosition": _world, "RoadPosition": _road_position, "LanePosition": _lane_position}
#: what an object's Init teleport reads besides (the other places need a position known without the entities)
TELEPORT_POSITIONS = POSITIONS | {"RelativeObjectPosition": _relative_object}


def read_position(elem: Element, roads: Mapping[str, Road], table: Mapping = POSITIONS) -> Pose:
    """A ``<Position>`` element's pose (``table``: :data:`TELEPORT_POSITIONS` in a teleport)."""
    return dispatch(one_child(elem), table, roads)


def resolve(pose: Pose, anchor: Pose) -> Pose:
    """A relative pose placed from its entity's pose ``anchor``: ``P = A + R(h_A) (dx, dy)``; it keeps its
    :class:`Relative`, so the object still reads as placed relative to an entity."""
    rel = pose.relative
    c, s = math.cos(anchor.h_rad), math.sin(anchor.h_rad)
    x = anchor.x_m + rel.dx_m * c - rel.dy_m * s
    y = anchor.y_m + rel.dx_m * s + rel.dy_m * c
    return Pose(x, y, rel.h_rad if rel.absolute else anchor.h_rad + rel.h_rad, relative=rel)
