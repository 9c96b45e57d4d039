"""OpenDRIVE ``<planView>``: the reference line's ``<geometry>`` records as crd's reference line.

Each ``<geometry s x y hdg length>`` holds one of (ASAM OpenDRIVE 1.7, 7.4-7.6):

* ``<line/>``: a straight line;
* ``<arc curvature>``: constant curvature (1/m, positive to the left);
* ``<spiral curvStart curvEnd>``: a clothoid, curvature linear in ``s``.

These map one to one onto :class:`cosim.world.reference_line.Line`, ``Arc`` and ``Spiral`` (and
onto ``[[road.geometry]]`` entries of a planar scenario). ``<poly3>`` and ``<paramPoly3>`` are
refused. Each record is placed by its own ``s x y hdg``; crd's ``[road]`` chains the pieces from
the first record's start, so each record must start where the previous one ends: within
``CONTINUITY_TOL_M`` in ``s``, ``x`` and ``y`` and ``CONTINUITY_TOL_RAD`` in heading (files round
their numbers), or the file is refused.
"""

from __future__ import annotations

import math
from typing import Any

from ...world.reference_line import Arc, Line, Placed, PlanView, Segment, Spiral
from .xml_source import Element, dispatch, fail, number, one_child, only, unsupported

CONTINUITY_TOL_M = 1e-4
CONTINUITY_TOL_RAD = 1e-5
POLYNOMIAL = "a polynomial reference line: crd's has lines, arcs and spirals (clothoids)"


def _make(elem: Element, make, *args) -> Segment:
    try:
        return make(*args)
    except ValueError as exc:
        raise fail(elem, str(exc)) from None


def _line(elem: Element, length_m: float) -> tuple[Segment, dict[str, Any]]:
    only(elem, ())
    return _make(elem, Line, length_m), {"kind": "line", "length_m": length_m}


def _arc(elem: Element, length_m: float) -> tuple[Segment, dict[str, Any]]:
    only(elem, ())
    k = number(elem, "curvature")
    return _make(elem, Arc, length_m, k), {"kind": "arc", "length_m": length_m, "curvature_1pm": k}


def _spiral(elem: Element, length_m: float) -> tuple[Segment, dict[str, Any]]:
    only(elem, ())
    k0, k1 = number(elem, "curvStart"), number(elem, "curvEnd")
    keys = {"kind": "spiral", "length_m": length_m, "curvature_start_1pm": k0, "curvature_end_1pm": k1}
    return _make(elem, Spiral, length_m, k0, k1), keys


def _polynomial(elem: Element, length_m: float) -> None:  # noqa: ARG001 - one handler signature
    raise unsupported(elem, POLYNOMIAL)


GEOMETRIES = {"line": _line, "arc": _arc, "spiral": _spiral, "poly3": _polynomial, "paramPoly3": _polynomial}


def _continues(geom: Element, placed: Placed, s_m: float, end: tuple[float, float, float]) -> None:
    """The record starts where the previous one ended."""
    x, y, h = end
    off_m = max(abs(s_m - placed.s_m), math.hypot(placed.x_m - x, placed.y_m - y))
    off_rad = abs(math.remainder(placed.heading_rad - h, 2 * math.pi))
    if off_m > CONTINUITY_TOL_M or off_rad > CONTINUITY_TOL_RAD:
        raise unsupported(geom, f"a reference line with a gap or a kink ({off_m:.3g} m, {off_rad:.3g} rad from the "
                                "previous geometry's end): crd's reference line is continuous")


def read_plan_view(plan: Element) -> tuple[PlanView, tuple[dict[str, Any], ...]]:
    """The reference line, and its pieces as ``[[road.geometry]]`` entries."""
    geoms = only(plan, ("geometry",))
    if not geoms:
        raise fail(plan, "expected at least one <geometry>")
    placed: list[Placed] = []
    keys: list[dict[str, Any]] = []
    for g in geoms:
        seg, entry = dispatch(one_child(g), GEOMETRIES, number(g, "length"))
        here = Placed(number(g, "s", 0.0), number(g, "x"), number(g, "y"), number(g, "hdg"), seg)
        if placed:
            prev = placed[-1]
            _continues(g, here, prev.s_m + prev.segment.length_m, prev.pose_at(prev.segment.length_m))
        elif here.s_m != 0.0:
            raise fail(g, f"s={here.s_m:g}: the first geometry starts at s = 0")
        placed.append(here)
        keys.append(entry)
    return PlanView(tuple(placed)), tuple(keys)


def is_straight(plan: PlanView) -> bool:
    """Lines only, all on the first one's heading: crd's 1-D world's road."""
    h0 = plan.placed[0].heading_rad
    return all(isinstance(p.segment, Line) and abs(math.remainder(p.heading_rad - h0, 2 * math.pi)) <= 1e-9
               for p in plan.placed)
