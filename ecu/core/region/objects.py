"""What the other objects occupy: a standing object its box, a moving one its own stopping region.

Input: :class:`TrackBox`, a radar track as the contract carries it (``can_dbc.planar.Track``: the
point of the object's box nearest the sensor, in the ego's frame from the front bumper, x forward,
y left; the velocity relative to the ego; the DBC size class) plus its position's standard
deviation ``sigma_m``.

**Box from the nearest point.** Per ego axis with coordinate ``c`` and the box's half extent ``h`` on
that axis (``h_x = a|cos phi| + b|sin phi|``, ``h_y = a|sin phi| + b|cos phi|``, ``a, b`` half length
and width, ``phi`` its heading): if ``|c| > k sigma`` the nearest point lies on the face toward
the ego and the centre is ``c + sign(c) h``; otherwise the face spans the sensor's axis and the
centre anywhere within ``c +- h``, so the box is widened by ``h`` on that axis (the union of every
box the report allows).

**Standing** (speed over ground ``|v_rel + (v_ego, 0)| <=`` ``moving_object_speed_mps``, as the 1-D
core): its box. Its heading is not measured, so it is taken as the road's where it stands
(:func:`standing_heading_rad`: parked and queued vehicles stand along the road; without a road, the
ego's heading), and the nearest point is placed in the box's own axes: the nearest point of a box to
the sensor is the sensor's position clamped into the box in those axes, per axis either on the face
toward the sensor or, within ``k sigma`` of the sensor's own coordinate, anywhere along that face.
Placed in the ego's axes instead, a car parked on the outside of a curve, turned with the road,
reports its corner near the bore sight and was widened across our lane.
**Moving**: the stopping region of :class:`ecu.core.region.params.ClassCapability`: the box swept
along its velocity ``phi = atan2(v_y, v_x)`` over ``s = v^2 / (2 d_c)``, widened on each side by
``min(y_max, a_lat t^2 / 2)``, ``t = v / d_c``. A region is a union over time, so an object that
brakes harder than ``d_c`` stays inside it (and the 1-D core's constant-speed assumption, which a
braking lead defeats, is not needed).

Both are inflated by ``k sigma`` (``sigma_factor``) on every side. The result, :class:`ObjectSet`,
holds oriented boxes (centre in the rear-axle frame of :mod:`ecu.core.region.paths`, unit axis,
half extents) as arrays of shape ``(K,)``.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numpy as np

from .params import CAPABILITIES, RegionParams
from .road import Road


class TrackBox(NamedTuple):
    """A track (SI, ego frame from the front bumper; velocity relative to the ego) and its position sigma."""

    x_m: float
    y_m: float
    vx_mps: float
    vy_mps: float
    size_class: int = 0
    sigma_m: float = 0.0


class ObjectSet(NamedTuple):
    """Oriented boxes the ego's stopping path must avoid, arrays of shape ``(K,)``: centre ``x + iy`` in the
    rear-axle frame, unit axis ``cos + i sin`` and its conjugate, half extents (m), and which are moving."""

    centre: np.ndarray
    axis: np.ndarray
    axis_conj: np.ndarray
    half_length_m: np.ndarray
    half_width_m: np.ndarray
    moving: np.ndarray


def _place(c: float, h: float, tol: float) -> tuple[float, float]:
    """(centre, widening) on one axis from the nearest point's coordinate ``c`` (module docstring)."""
    if abs(c) > tol:
        return c + math.copysign(h, c), 0.0
    return c, h


def standing_heading_rad(x_m: float, y_m: float, road: Road | None) -> float:
    """The heading (relative to the ego) of the road at the point ``(x, y)`` of the rear-axle frame: of the
    reference line through the rear axle (heading ``psi``, curvature ``kappa``, :class:`~ecu.core.region.road.Road`)
    at the point's radial projection, ``psi + atan2(kappa t, 1 - kappa n)`` with ``(t, n)`` the point in the line's
    axes at the rear axle (exact on the circle; ``psi`` on a straight line); 0 without a road."""
    if road is None:
        return 0.0
    c, s = math.cos(road.heading_rad), math.sin(road.heading_rad)
    t, n = x_m * c + y_m * s, y_m * c - x_m * s
    return road.heading_rad + math.atan2(road.curvature_1pm * t, 1.0 - road.curvature_1pm * n)


def standing_box(track: TrackBox, params: RegionParams, road: Road | None) -> tuple[float, ...]:
    """:func:`object_box` of a standing track: its box along the road where it stands, placed in its own axes."""
    x, y, _, _, size_class, sigma = track
    cap = CAPABILITIES.get(size_class, CAPABILITIES[0])
    a, b, tol = 0.5 * cap.length_m, 0.5 * cap.width_m, params.sigma_factor * sigma
    heading = standing_heading_rad(x + params.rear_axle_to_front_m, y, road)
    c, s = math.cos(heading), math.sin(heading)
    cu, wu = _place(x * c + y * s, a, tol)
    cw, ww = _place(y * c - x * s, b, tol)
    return (cu * c - cw * s + params.rear_axle_to_front_m, cu * s + cw * c, c, s, a + wu + tol, b + ww + tol, 0.0)


def object_box(track: TrackBox, ego_speed_mps: float, params: RegionParams,
               road: Road | None = None) -> tuple[float, ...]:
    """(x, y, cos, sin, half length, half width, moving) of one track (module docstring); a standing one along the
    ``road`` (:func:`standing_box`). Scalar code: for eight tracks it is faster than numpy's per-call overhead."""
    x, y, vx, vy, size_class, sigma = track
    length, width, decel, lat, reach = CAPABILITIES.get(size_class, CAPABILITIES[0])
    vx += ego_speed_mps
    speed = math.hypot(vx, vy)
    if speed <= params.moving_object_speed_mps:
        return standing_box(track, params, road)
    c, s = vx / speed, vy / speed
    a, b, ac, as_ = 0.5 * length, 0.5 * width, abs(c), abs(s)
    tol = params.sigma_factor * sigma
    cx, wx = _place(x, a * ac + b * as_, tol)
    cy, wy = _place(y, a * as_ + b * ac, tol)
    sweep = speed * speed / (2.0 * decel)
    side = min(reach, 0.5 * lat * (speed / decel) ** 2)
    return (cx + 0.5 * sweep * c + params.rear_axle_to_front_m, cy + 0.5 * sweep * s, c, s,
            a + wx * ac + wy * as_ + 0.5 * sweep + tol, b + wx * as_ + wy * ac + side + tol, 1.0)


def object_set(tracks: Sequence[TrackBox], ego_speed_mps: float, params: RegionParams,
               road: Road | None = None) -> ObjectSet:
    """The boxes of every track: standing boxes and moving stopping regions, inflated (module docstring)."""
    return boxes_as_set([object_box(t, ego_speed_mps, params, road) for t in tracks])


def boxes_as_set(boxes: Sequence[tuple[float, ...]]) -> ObjectSet:
    """:func:`object_box` es as an :class:`ObjectSet`."""
    rows = np.array(boxes, dtype=float).reshape(-1, 7)
    centre = rows[:, 0:2].copy().view(complex).ravel()
    axis = rows[:, 2:4].copy().view(complex).ravel()
    return ObjectSet(centre, axis, np.conj(axis), rows[:, 4].copy(), rows[:, 5].copy(), rows[:, 6] > 0.0)


def corners(objects: ObjectSet) -> np.ndarray:
    """The four corners of every box as complex points, shape ``(K, 4)``, counter-clockwise from front left."""
    local = (np.array([1.0, -1.0, -1.0, 1.0])[None, :] * objects.half_length_m[:, None]
             + 1j * np.array([1.0, 1.0, -1.0, -1.0])[None, :] * objects.half_width_m[:, None])
    return objects.centre[:, None] + objects.axis[:, None] * local
