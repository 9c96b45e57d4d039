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
core): its box, aligned with the ego (a standing object's heading is not measured).
**Moving**: the stopping region of :class:`ecu.core.region.params.ClassCapability`: the box swept
along its velocity ``phi = atan2(v_y, v_x)`` over ``s = (v + a rho / 2) rho + v_rho^2 / (2 d_c)``,
``v_rho = v + a rho`` (its response time ``rho`` at acceleration ``a``, then its braking), widened on each
side by ``min(y_max, a_lat t^2 / 2)``, ``t = rho + v_rho / d_c``. A region is a union over time, so an object that
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


def object_box(track: TrackBox, ego_speed_mps: float, params: RegionParams) -> tuple[float, ...]:
    """(x, y, cos, sin, half length, half width, moving) of one track (module docstring); scalar code:
    for eight tracks it is faster than numpy's per-call overhead."""
    x, y, vx, vy, size_class, sigma = track
    length, width, decel, lat, reach, response, accel = CAPABILITIES.get(size_class, CAPABILITIES[0])
    vx += ego_speed_mps
    speed = math.hypot(vx, vy)
    moving = speed > params.moving_object_speed_mps
    c, s = (vx / speed, vy / speed) if moving else (1.0, 0.0)
    a, b, ac, as_ = 0.5 * length, 0.5 * width, abs(c), abs(s)
    tol = params.sigma_factor * sigma
    cx, wx = _place(x, a * ac + b * as_, tol)
    cy, wy = _place(y, a * as_ + b * ac, tol)
    sweep = side = 0.0
    if moving:
        fast = speed + accel * response
        sweep = (speed + 0.5 * accel * response) * response + fast * fast / (2.0 * decel)
        side = min(reach, 0.5 * lat * (response + fast / decel) ** 2)
    return (cx + 0.5 * sweep * c + params.rear_axle_to_front_m, cy + 0.5 * sweep * s, c, s,
            a + wx * ac + wy * as_ + 0.5 * sweep + tol, b + wx * as_ + wy * ac + side + tol, float(moving))


def object_set(tracks: Sequence[TrackBox], ego_speed_mps: float, params: RegionParams) -> ObjectSet:
    """The boxes of every track: standing boxes and moving stopping regions, inflated (module docstring)."""
    return boxes_as_set([object_box(t, ego_speed_mps, params) for t in tracks])


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
