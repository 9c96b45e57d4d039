"""The OpenDRIVE subset crd reads: reference lines of lines, arcs and spirals, and lanes of constant width.

A road's reference line is one or more ``<line>``, ``<arc>`` or ``<spiral>`` geometries
(:mod:`.plan_view`); ``<poly3>`` and ``<paramPoly3>`` are refused. Lanes: one ``<laneSection>``,
each lane one ``<width>`` with only the constant term ``a`` (``b = c = d = 0``), and a constant
``<laneOffset>``. Road marks and road types are accepted and have no effect (crd's radar sees no
paint). Anything else is a one-line error naming the file, the line and the element. Junctions are
refused.

Road coordinates (ASAM OpenDRIVE 1.7, 7.4): a point at ``(s, t)`` lies at
``p(s) + t (-sin h(s), cos h(s))`` with ``p(s)`` and ``h(s)`` the reference line's point and heading
at ``s``, ``t`` positive to the left. The centre of lane ``k < 0`` (right of the centre lane) is at
``t = offset - sum(w_-1 .. w_k+1) - w_k / 2``; of ``k > 0`` at
``t = offset + sum(w_1 .. w_k-1) + w_k / 2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ...world.reference_line import PlanView
from .plan_view import is_straight, read_plan_view
from .xml_source import Element, child, children, dispatch, fail, number, only, parse_file, unsupported

PLANAR = "needs an object moving in the plane: crd's 1-D objects move along and across the ego's start heading"


@dataclass(frozen=True)
class Road:
    """One road: its reference line, its pieces as ``[[road.geometry]]`` entries, and its lanes (m)."""

    road_id: str
    plan: PlanView
    geometry: tuple[dict[str, Any], ...]
    length_m: float
    lane_centre_t_m: dict[int, float] = field(default_factory=dict)
    lane_width_m: dict[int, float] = field(default_factory=dict)
    lane_offset_m: float = 0.0

    @property
    def straight(self) -> bool:
        """Lines on one heading: the road crd's 1-D world drives."""
        return is_straight(self.plan)

    @property
    def hdg_rad(self) -> float:
        """The reference line's heading at its start."""
        return self.plan.placed[0].heading_rad

    def heading_at(self, s_m: float) -> float:
        """The reference line's heading at ``s``."""
        return self.plan.pose_at(s_m)[2]

    def point(self, s_m: float, t_m: float) -> tuple[float, float]:
        """World ``(x, y)`` of road coordinates ``(s, t)``."""
        x, y, h = self.plan.pose_at(s_m)
        return x - t_m * math.sin(h), y + t_m * math.cos(h)

    def offset_of(self, x_m: float, y_m: float) -> float:
        """The road offset ``t`` of a world point (a straight road's)."""
        x0, y0, h = self.plan.pose_at(0.0)
        return -(x_m - x0) * math.sin(h) + (y_m - y0) * math.cos(h)

    def lane_at(self, t_m: float) -> int | None:
        """The lane whose span holds the offset ``t`` (None: off the lanes)."""
        for lane, centre in self.lane_centre_t_m.items():
            if abs(t_m - centre) <= self.lane_width_m[lane] / 2:
                return lane
        return None


def _polynomial_constant(elem: Element, name: str = "a") -> float:
    for coef in ("b", "c", "d"):
        if number(elem, coef, 0.0) != 0.0:
            raise unsupported(elem, f"{coef}={elem.get(coef)}: crd reads constant values (only {name})")
    return number(elem, name)


def _lane_width(lane: Element) -> float:
    kids = only(lane, ("link", "width", "roadMark", "userData"))
    widths = [k for k in kids if k.tag == "width"]
    if len(widths) != 1:
        raise unsupported(lane, f"{len(widths)} <width> records: crd reads one constant width per lane")
    if number(widths[0], "sOffset", 0.0) != 0.0:
        raise unsupported(widths[0], "a width starting after the section's start")
    return _polynomial_constant(widths[0])


def _side(side: Element | None, sign: int) -> dict[int, float]:
    if side is None:
        return {}
    widths = {}
    for lane in only(side, ("lane",)):
        lane_id = int(number(lane, "id"))
        if lane_id == 0 or (lane_id > 0) != (sign > 0):
            raise fail(lane, f"lane id {lane_id} on the wrong side")
        widths[lane_id] = _lane_width(lane)
    return widths


def _lanes(lanes: Element) -> tuple[dict[int, float], dict[int, float], float]:
    kids = only(lanes, ("laneOffset", "laneSection"))
    offsets = [k for k in kids if k.tag == "laneOffset"]
    sections = [k for k in kids if k.tag == "laneSection"]
    if len(sections) != 1 or len(offsets) > 1:
        raise unsupported(lanes, f"{len(sections)} lane sections and {len(offsets)} lane offsets: crd reads one each")
    offset = _polynomial_constant(offsets[0]) if offsets else 0.0
    section = sections[0]
    only(section, ("left", "center", "right", "userData"))
    widths = _side(child(section, "right", False), -1) | _side(child(section, "left", False), 1)
    centres = {}
    for lane, w in widths.items():
        sign = 1 if lane > 0 else -1
        inner = sum(widths.get(sign * k, 0.0) for k in range(1, abs(lane)))
        centres[lane] = offset + sign * (inner + w / 2)
    return centres, widths, offset


def _flat(elem: Element) -> None:
    for k in children(elem):
        if k.tag not in ("elevation", "superelevation", "shape"):
            raise unsupported(k)
        if any(number(k, c, 0.0) != 0.0 for c in ("a", "b", "c", "d")):
            raise unsupported(k, "a road that is not flat: crd's plant drives on the level")


def _empty_link(elem: Element) -> None:
    for k in children(elem):
        if k.tag not in ("predecessor", "successor"):
            raise unsupported(k)


ROAD_PARTS = {"link": _empty_link, "type": lambda e: None, "planView": read_plan_view, "elevationProfile": _flat,
              "lateralProfile": _flat, "lanes": _lanes, "userData": lambda e: None}


def _road(elem: Element) -> Road:
    if elem.get("junction", "-1") != "-1":
        raise unsupported(elem, "a road inside a junction")
    parts = {k.tag: dispatch(k, ROAD_PARTS) for k in children(elem)}
    if "planView" not in parts or "lanes" not in parts:
        raise fail(elem, "expected <planView> and <lanes>")
    (plan, geometry), (centres, widths, offset) = parts["planView"], parts["lanes"]
    if offset != 0.0 and not is_straight(plan):
        raise unsupported(child(child(elem, "lanes"), "laneOffset"), "a lane offset on a curved road: crd's lanes "
                                                                       "lie beside the reference line")
    return Road(elem.get("id", ""), plan, geometry, number(elem, "length"), centres, widths, offset)


def read_opendrive(path: Path) -> dict[str, Road]:
    """The roads of an OpenDRIVE file, by id."""
    root = parse_file(path, "OpenDRIVE")
    roads: dict[str, Road] = {}
    for elem in only(root, ("header", "road")):
        if elem.tag == "header":
            only(elem, ())
            continue
        road = _road(elem)
        roads[road.road_id] = road
    if not roads:
        raise fail(root, "expected at least one <road>")
    return roads
