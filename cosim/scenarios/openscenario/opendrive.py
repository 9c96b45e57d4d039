"""The OpenDRIVE subset crd reads: straight reference lines and lanes of constant width.

A road's reference line is one or more ``<line>`` geometries on one heading;
``<arc>``, ``<spiral>``, ``<poly3>`` and ``<paramPoly3>`` need the planar world
(issue 21) and are refused until it lands. Lanes: one ``<laneSection>``, each
lane one ``<width>`` with only the constant term ``a`` (``b = c = d = 0``), and a
constant ``<laneOffset>``. Road marks and road types are accepted and have no
effect (crd's radar sees no paint). Anything else is a one-line error naming
the file, the line and the element. Junctions are refused.

Road coordinates (ASAM OpenDRIVE 1.7, 7.4): a point at ``(s, t)`` lies at
``(x0, y0) + s (cos hdg, sin hdg) + t (-sin hdg, cos hdg)``, ``t`` positive to
the left. The centre of lane ``k < 0`` (right of the centre lane) is at
``t = offset - sum(w_-1 .. w_k+1) - w_k / 2``; of ``k > 0`` at
``t = offset + sum(w_1 .. w_k-1) + w_k / 2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from .xml_source import Element, child, children, dispatch, fail, number, one_child, only, parse_file, unsupported

HEADING_TOL_RAD = 1e-9
PLANAR = "needs the planar world (issue 21), which lands later; crd's road is straight for now"


@dataclass(frozen=True)
class Road:
    """One straight road: its reference line and its lanes' centre offsets ``t`` (m)."""

    road_id: str
    x0_m: float
    y0_m: float
    hdg_rad: float
    length_m: float
    lane_centre_t_m: dict[int, float] = field(default_factory=dict)
    lane_width_m: dict[int, float] = field(default_factory=dict)

    def point(self, s_m: float, t_m: float) -> tuple[float, float]:
        """World ``(x, y)`` of road coordinates ``(s, t)``."""
        c, s = math.cos(self.hdg_rad), math.sin(self.hdg_rad)
        return self.x0_m + s_m * c - t_m * s, self.y0_m + s_m * s + t_m * c

    def offset_of(self, x_m: float, y_m: float) -> float:
        """The road offset ``t`` of a world point."""
        return -(x_m - self.x0_m) * math.sin(self.hdg_rad) + (y_m - self.y0_m) * math.cos(self.hdg_rad)

    def lane_at(self, t_m: float) -> int | None:
        """The lane whose span holds the offset ``t`` (None: off the lanes)."""
        for lane, centre in self.lane_centre_t_m.items():
            if abs(t_m - centre) <= self.lane_width_m[lane] / 2:
                return lane
        return None


def _line(elem: Element) -> None:
    only(elem, ())


def _curved(elem: Element) -> None:
    raise unsupported(elem, PLANAR)


GEOMETRIES = {"line": _line, "arc": _curved, "spiral": _curved, "poly3": _curved, "paramPoly3": _curved}


def _plan_view(plan: Element) -> tuple[float, float, float]:
    """Start point and heading of a straight reference line of one or more collinear lines."""
    geoms = only(plan, ("geometry",))
    if not geoms:
        raise fail(plan, "expected at least one <geometry>")
    first = geoms[0]
    x0, y0, hdg = number(first, "x"), number(first, "y"), number(first, "hdg")
    for g in geoms:
        dispatch(one_child(g), GEOMETRIES)
        if abs(number(g, "hdg") - hdg) > HEADING_TOL_RAD:
            raise unsupported(g, f"a change of heading along the road; {PLANAR}")
    return x0, y0, hdg


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


def _lanes(lanes: Element) -> tuple[dict[int, float], dict[int, float]]:
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
    return centres, widths


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


ROAD_PARTS = {"link": _empty_link, "type": lambda e: None, "planView": _plan_view, "elevationProfile": _flat,
              "lateralProfile": _flat, "lanes": _lanes, "userData": lambda e: None}


def _road(elem: Element) -> Road:
    if elem.get("junction", "-1") != "-1":
        raise unsupported(elem, "a road inside a junction")
    parts = {k.tag: dispatch(k, ROAD_PARTS) for k in children(elem)}
    if "planView" not in parts or "lanes" not in parts:
        raise fail(elem, "expected <planView> and <lanes>")
    (x0, y0, hdg), (centres, widths) = parts["planView"], parts["lanes"]
    return Road(elem.get("id", ""), x0, y0, hdg, number(elem, "length"), centres, widths)


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
