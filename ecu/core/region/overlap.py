"""Overlap of the sampled stopping paths with the objects, and with the road's bounds, vectorised.

**Footprint.** Box ``k`` of a path is the ego's box at pose ``k`` (rear axle; ``x`` from
``R - L`` to ``R``, ``R`` the rear axle to the front bumper, and to ``R + standoff`` for the last
box, where the car stops; ``y`` within
``+-(W/2 + lateral_margin)``) stretched back by the sample spacing ``ds`` so that it covers the
motion since pose ``k - 1``. Along an arc of curvature ``kappa`` (the path's largest) a body point ``(o_x, o_y)`` seen
``t <= ds`` earlier lies, in pose ``k``'s frame, at ``(o_x - t + kappa t o_y, o_y + kappa t (t/2 - o_x))``
to first order in ``kappa t`` (our derivation). Over ``0 <= t <= ds`` the excursion ``t (t/2 - o_x)`` is largest
at the rear overhang ``o_x = -r`` (inward, ``ds (ds/2 + r)``) or at the front reach ``o_x = f`` (outward,
``ds (f - ds/2)``, or ``f^2/2`` once ``ds > f``), so the box grows by
``e_y = |kappa| max(ds (ds/2 + r), ds (f - ds/2)) + (kappa ds)^2 (max|o_x| + W/2) / 2`` across and
``e_x = |kappa| ds W/2 + e_y`` along (second-order term as a margin;
``tests/ecu/region/test_overlap.py`` checks the cover against densely sampled poses). The bound
``|kappa| ds (ds/2 + max|o_x|)``, which adds the two sides' worst terms, grew the box by more than twice
the motion it covers.

**Separation.** For every path, pose and object: the object's box projected on the pose's axes
(half extents ``h_x = a|cos b| + b_w|sin b|``, ``h_y = a|sin b| + b_w|cos b|``, ``b`` the heading
difference) against the footprint; the gap is the larger of the two axis gaps::

    g = max(|l_x - m_x| - w_x - h_x,  |l_y| - w_y - h_y)

``(l_x, l_y)`` the object's centre in the pose's frame, ``m_x, w_x`` the footprint's middle and
half length, ``w_y`` its half width. This is the separating-axis test on the pose's two axes; where it
does not separate (``g < 0``), the object's two axes are tried too (:func:`_object_axes`), so the verdict
is the full test's, exact for two boxes, while a positive ``g`` stays the two-axis value (exact when the
two are aligned, as in the 1-D case, where ``g = r - d - standoff``). ``g >= 0``: disjoint; the clearance
of a path is its smallest ``g``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .objects import ObjectSet
from .params import RegionParams
from .paths import PathSet


class Footprint(NamedTuple):
    """Per row and pose (shape ``(N, M, 1)``): the box's middle and half length along x; per row
    (``(N, 1, 1)``) its half width."""

    mid_x_m: np.ndarray
    half_x_m: np.ndarray
    half_y_m: np.ndarray


def footprint(paths: PathSet, params: RegionParams) -> Footprint:
    """The stretched and widened box of every row and pose (module docstring); the standoff extends the
    last box only, where the car stops (the 1-D core's ``d + standoff <= r``). Scalar code per row (compiled,
    ``setup.py``): for 16 rows cheaper than numpy's calls."""
    front = params.rear_axle_to_front_m + params.standoff_m
    overhang = params.length_m - params.rear_axle_to_front_m
    reach = max(front, overhang)
    half_w, rear = 0.5 * params.width_m, params.rear_axle_to_front_m - 0.5 * params.length_m
    stops: list[float] = paths.stop_m.tolist()
    curvatures: list[float] = paths.max_curvature_1pm.tolist()
    mid_x, half_x, half_y = [], [], []
    for stop, kappa in zip(stops, curvatures):
        ds = stop * (1.0 / params.path_samples)
        turn = kappa * ds
        excursion = max(ds * (0.5 * ds + overhang), ds * (front - 0.5 * ds) if ds <= front else 0.5 * front * front)
        grow_y = kappa * excursion + (0.5 * (reach + half_w)) * (turn * turn)
        half_x.append(0.5 * (params.length_m + ds) + (turn * half_w + grow_y))  # stretched rear to front, grown
        mid_x.append(rear - 0.5 * ds)
        half_y.append((half_w + params.lateral_margin_m) + grow_y)
    standoff = 0.5 * params.standoff_at_samples_m
    return Footprint((np.array(mid_x)[:, None] + standoff)[..., None],
                     (np.array(half_x)[:, None] + standoff)[..., None], np.array(half_y)[:, None, None])


def gaps(paths: PathSet, objects: ObjectSet, box: Footprint) -> np.ndarray:
    """Separation ``g`` (m) of every row, pose and object, shape ``(N, M, K)`` (module docstring): a view of
    :func:`object_gaps`."""
    return object_gaps(paths, objects, box).transpose(1, 2, 0)


def object_gaps(paths: PathSet, objects: ObjectSet, box: Footprint) -> np.ndarray:
    """Separation ``g`` (m) of every object, row and pose, shape ``(K, N, M)`` (module docstring).

    Complex arithmetic: the object's centre in the pose's frame is ``(o - z) conj(h)`` and the heading
    difference ``conj(u) h`` (``z, h`` the pose's position and heading, ``o, u`` the object's). Objects
    first: the rows and poses, contiguous, make each operation's inner loop (``N M`` long, not ``K``)."""
    heading = paths.heading
    local = (objects.centre[:, None, None] - paths.position) * np.conj(heading)
    turn = objects.axis_conj[:, None, None] * heading
    rc, rs = np.abs(turn.real), np.abs(turn.imag)
    a, b = objects.half_length_m[:, None, None], objects.half_width_m[:, None, None]
    gx = np.abs(local.real - box.mid_x_m[..., 0])
    gx -= box.half_x_m[..., 0]
    gx -= a * rc
    gx -= b * rs
    gy = np.abs(local.imag)
    gy -= box.half_y_m[..., 0]
    gy -= a * rs
    gy -= b * rc
    g = np.maximum(gx, gy, out=gx)
    if g.min(initial=0.0) < 0.0:
        _object_axes(g, local - box.mid_x_m[..., 0], turn, (a, b), box)
    return g


def _object_axes(g: np.ndarray, offset: np.ndarray, turn: np.ndarray, half: tuple[np.ndarray, np.ndarray],
                 box: Footprint) -> None:
    """Where ``g < 0``, the separating-axis test's other two axes, the object's: ``g = max(g, g_u, g_w)`` with the
    footprint box projected on them (``offset``: the object's centre from the box's middle, pose axes; ``turn``: the
    pose's heading in the object's axes; ``half``: the object's half extents). Only where the pose's axes do not
    separate, so every disjoint gap, and every clearance and proximity built on them, is the two-axis test's; a
    long box turned against the pose (a parked car beside us, widened along its side) no longer touches a
    footprint its own axes separate it from."""
    local = offset * turn
    rc, rs = np.abs(turn.real), np.abs(turn.imag)
    fx, fy = box.half_x_m[..., 0], box.half_y_m[..., 0]
    gu = np.abs(local.real) - half[0] - fx * rc - fy * rs
    gw = np.abs(local.imag) - half[1] - fx * rs - fy * rc
    np.maximum(g, np.where(g < 0.0, np.maximum(gu, gw), g), out=g)


def row_gaps(paths: PathSet, objects: ObjectSet, box: Footprint, row: int) -> np.ndarray:
    """:func:`object_gaps` of the one ``row``, shape ``(K, M)``: the same values (each is computed alone), for the
    work of one row."""
    one = slice(row, row + 1)
    return object_gaps(paths._replace(position=paths.position[one], heading=paths.heading[one]), objects,
                       Footprint(box.mid_x_m[one], box.half_x_m[one], box.half_y_m[one]))[:, 0]


def corner_points(paths: PathSet, box: Footprint) -> np.ndarray:
    """The corners (front left, rear left, rear right, front right) of every footprint box as complex points,
    shape ``(N, M, 4)`` (road test, drawing)."""
    local = np.empty((*paths.position.shape, 4), complex)
    local.real[..., ::3] = box.mid_x_m + box.half_x_m  # front left, front right
    local.real[..., 1:3] = box.mid_x_m - box.half_x_m  # rear left, rear right
    local.imag[..., :2] = box.half_y_m
    local.imag[..., 2:] = -box.half_y_m
    return paths.position[..., None] + paths.heading[..., None] * local


def speed_at_mps(paths: PathSet, s_m: list[float]) -> np.ndarray:
    """Speed (m/s) of every row at its arc length ``s_m`` (one per row): ``v^2 + 2 a s`` in the hold, then
    ``v_h^2 (1 - (s - d_hold) / s_brake)``, the braking's mean deceleration (an approximation of the
    friction-circle profile that ranks paths by impact speed). Scalar code per row, as :func:`footprint`."""
    speeds = []
    rows = zip(paths.hold_speed_mps.tolist(), paths.hold_m.tolist(), paths.accel_mps2.tolist(), paths.stop_m.tolist())
    for s, (v_h, hold, a, stop) in zip(s_m, rows):
        v_h_sq = v_h * v_h
        if s <= hold:
            speeds.append(math.sqrt(max(v_h_sq - 2.0 * a * (hold - s), 0.0)))
        else:
            speeds.append(math.sqrt(v_h_sq * max(1.0 - (s - hold) / max(stop - hold, 1e-9), 0.0)))
    return np.array(speeds)
