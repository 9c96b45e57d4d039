"""The road and its lanes, as the emergency-steering rule needs them.

UN R79's emergency steering function "must not lead the vehicle off the road ... nor into another
road user" (planar-protocol-facts.md section 4, S5); issue 22 adds: never into a lane that another
track occupies. :class:`Road` gives the lane boundaries as lateral offsets, right to left, from
the ego's rear axle (the origin of :mod:`ecu.core.region.paths`), of a road reference line through
that point with heading ``psi`` (relative to the ego) and curvature ``kappa_r``. A point
``p = (x, y)`` has the road coordinates (second order in ``kappa_r t``, our approximation; on a
100 m radius the error at 30 m is ``kappa_r^2 t^3 / 6`` ~ 4.5 cm)::

    t = x cos(psi) + y sin(psi),   e = -x sin(psi) + y cos(psi) - kappa_r t^2 / 2

The steering paths may use the span of lanes from the ego's own lane outward up to the first
lane that holds another object's centre, and never beyond the outermost boundaries.
"""

from __future__ import annotations

import bisect
import math
from typing import NamedTuple, cast

import numpy as np


class Road(NamedTuple):
    """Lane boundaries (m, left positive, strictly increasing) of a reference line through the rear axle."""

    boundaries_m: tuple[float, ...]
    heading_rad: float = 0.0
    curvature_1pm: float = 0.0


def lateral_offsets(road: Road, points: np.ndarray) -> np.ndarray:
    """``e`` of complex points ``x + iy`` (module docstring), same shape; a reference line along the ego's heading
    (``psi = 0``, the ECU's assumed road) needs no rotation, a straight one no curvature term (both exact)."""
    rotated = points if road.heading_rad == 0.0 else points * complex(math.cos(road.heading_rad),
                                                                      -math.sin(road.heading_rad))
    if road.curvature_1pm == 0.0:
        return rotated.imag
    t = rotated.real
    return rotated.imag - (0.5 * road.curvature_1pm) * (t * t)


def allowed_span(road: Road, object_offsets_m: np.ndarray) -> tuple[float, float]:
    """(e_lo, e_hi): the ego's lane widened outward over free lanes; an empty span (lo > hi) when the ego
    is off the road. A lane holding an object's centre (``object_offsets_m``) ends the span."""
    bounds = road.boundaries_m
    own = bisect.bisect_right(bounds, 0.0) - 1
    if own < 0 or own >= len(bounds) - 1:
        return math.inf, -math.inf
    occupied = {bisect.bisect_right(bounds, e) - 1 for e in object_offsets_m.tolist()} - {own}
    lo = own
    while lo - 1 >= 0 and lo - 1 not in occupied:
        lo -= 1
    hi = own
    while hi + 1 < len(bounds) - 1 and hi + 1 not in occupied:
        hi += 1
    return bounds[lo], bounds[hi + 1]


def on_road(road: Road, corners: np.ndarray, span: tuple[float, float]) -> np.ndarray:
    """Per row: every corner of every footprint box (complex, shape ``(N, M, 4)``) lies within ``span``."""
    e = lateral_offsets(road, corners)
    return cast(np.ndarray, ((e >= span[0]) & (e <= span[1])).all(axis=(1, 2)))
