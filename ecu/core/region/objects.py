"""What the other objects occupy: a standing object its box, a moving one its own stopping region.

Input: :class:`TrackBox`, a radar track as the contract carries it (``can_dbc.planar.Track``: the
point of the object's box nearest the sensor, in the ego's frame from the front bumper, x forward,
y left; the velocity relative to the ego; the DBC size class) plus its position's standard
deviation ``sigma_m``.

**Box from the nearest point**, in the box's own axes (heading ``phi``; ``a, b`` half length and
width): the nearest point of a box to the sensor is the sensor's position clamped into the box in
those axes, so per axis, with the nearest point's coordinate ``c`` there and the half extent ``h``: if
``|c| > k sigma`` the point lies on the face toward the sensor and the centre is ``c + sign(c) h``;
otherwise the face spans the sensor's axis and the centre lies anywhere within ``c +- h``, so the box
is widened by ``h`` on that axis (the union of every box the report allows). This is exact for the
box, whatever its heading; in the ego's axes, with the turned box's bounding extents, it was not: a
car parked on the outside of a curve, turned with the road, or an oncoming car in it showed a corner
near the bore sight and was widened across our lane, and a little further on put on the wrong side of
that corner.

**Standing** (speed over ground ``|v_rel + (v_ego, 0)| <=`` ``moving_object_speed_mps``, as the 1-D
core): its box. Its heading is not measured, so it is taken as the road's where it stands
(:func:`standing_heading_rad`: parked and queued vehicles stand along the road; without a road, the
ego's heading).
The tolerance ``k sigma`` grows by ``r sin(d_phi)`` for a moving object, ``r`` the nearest point's range and
``sin(d_phi) = min(1, v_tol / v)`` the uncertainty of its heading from that of its velocity over ground
(``velocity_tolerance_mps``: the radar's relative velocity is a latency old, the ego's speed this cycle's):
a turn of the axes by ``d_phi`` about the sensor moves the point that much in them (a car crossing just
ahead, its heading 5 degrees off, showed its nearest point 0.7 m off its side's middle and was put
beside our axis instead of across it, its region missing part of it:
``tests/ecu/region/test_objects.py``); it decides the placement, the inflation stays ``k sigma``. A
standing object's heading is taken as exact. ``velocity_tolerance_mps`` is 0 by default, so the term is off
(:class:`ecu.core.region.params.RegionParams` says why: a cyclist passed at 1.5 m).
**Moving**: heading along its velocity ``phi = atan2(v_y, v_x)``, it occupies the stopping region of
:class:`ecu.core.region.params.ClassCapability`: the box swept along ``phi`` over
``s = (v + a rho / 2) rho + v_rho^2 / (2 d_c)``, ``v_rho = v + a rho`` (its response time ``rho`` at
acceleration ``a``, then its braking), widened on each side by ``min(y_max, a_lat t^2 / 2)``,
``t = rho + v_rho / d_c``. A region is a union over time, so an object that brakes harder than ``d_c``
stays inside it (and the 1-D core's constant-speed assumption, which a braking lead defeats, is not
needed).

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


def object_box(track: TrackBox, ego_speed_mps: float, params: RegionParams,
               road: Road | None = None) -> tuple[float, ...]:
    """(x, y, cos, sin, half length, half width, moving) of one track (module docstring); a standing one along the
    ``road``. Scalar code: for eight tracks it is faster than numpy's per-call overhead."""
    x, y, vx, vy, size_class, sigma = track
    length, width, decel, lat, reach, response, accel = CAPABILITIES.get(size_class, CAPABILITIES[0])
    vx += ego_speed_mps
    speed = math.hypot(vx, vy)
    moving = speed > params.moving_object_speed_mps
    if moving:
        c, s = vx / speed, vy / speed
    else:
        heading = standing_heading_rad(x + params.rear_axle_to_front_m, y, road)
        c, s = math.cos(heading), math.sin(heading)
    a, b, tol = 0.5 * length, 0.5 * width, params.sigma_factor * sigma
    # the heading's own uncertainty turns the box's axes about the sensor: r sin(d_phi) more on each (docstring)
    turned = math.hypot(x, y) * min(1.0, params.velocity_tolerance_mps / speed) if moving else 0.0
    cu, wu = _place(x * c + y * s, a, tol + turned)
    cw, ww = _place(y * c - x * s, b, tol + turned)
    sweep = side = 0.0
    if moving:
        fast = speed + accel * response
        sweep = (speed + 0.5 * accel * response) * response + fast * fast / (2.0 * decel)
        side = min(reach, 0.5 * lat * (response + fast / decel) ** 2)
        cu += 0.5 * sweep
    return (cu * c - cw * s + params.rear_axle_to_front_m, cu * s + cw * c, c, s,
            a + wu + 0.5 * sweep + tol, b + ww + side + tol, float(moving))


def object_set(tracks: Sequence[TrackBox], ego_speed_mps: float, params: RegionParams,
               road: Road | None = None) -> ObjectSet:
    """The boxes of every track: standing boxes and moving stopping regions, inflated (module docstring)."""
    return boxes_as_set([object_box(t, ego_speed_mps, params, road) for t in tracks])


def boxes_as_set(boxes: Sequence[tuple[float, ...]]) -> ObjectSet:
    """:func:`object_box` es as an :class:`ObjectSet`: one array built per field from the boxes (for eight boxes
    cheaper than one array of them cut into fields)."""
    axis = np.array([complex(box[2], box[3]) for box in boxes], dtype=complex)
    return ObjectSet(np.array([complex(box[0], box[1]) for box in boxes], dtype=complex), axis, np.conj(axis),
                     np.array([box[4] for box in boxes], dtype=float), np.array([box[5] for box in boxes], dtype=float),
                     np.array([box[6] > 0.0 for box in boxes], dtype=bool))


def corners(objects: ObjectSet) -> np.ndarray:
    """The four corners of every box as complex points, shape ``(K, 4)``, counter-clockwise from front left."""
    local = (np.array([1.0, -1.0, -1.0, 1.0])[None, :] * objects.half_length_m[:, None]
             + 1j * np.array([1.0, 1.0, -1.0, -1.0])[None, :] * objects.half_width_m[:, None])
    return objects.centre[:, None] + objects.axis[:, None] * local
