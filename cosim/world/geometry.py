"""Oriented boxes in the plane: overlap, contact point and normal, and the impact speed along the normal.

A :class:`Box` is a rectangle with centre ``(x_m, y_m)``, heading ``yaw_rad``
(counter-clockwise from the world x axis), ``length_m`` along its heading and
``width_m`` across it; its unit axes are ``u = (cos yaw, sin yaw)`` and
``n = (-sin yaw, cos yaw)``. Boxes are closed sets: boxes that touch overlap.

**Overlap, separating-axis test** (Gottschalk, Lin, Manocha, "OBBTree",
SIGGRAPH 1996; Ericson, *Real-Time Collision Detection*, 2005, §4.4.1). Two
convex polygons are disjoint iff some edge normal of either one separates
them; a rectangle has two distinct edge normals, so four axes ``L`` decide.
Along ``L`` the boxes overlap by::

    o(L) = r_a(L) + r_b(L) - |(c_b - c_a) . L|,   r(L) = (l/2) |u . L| + (w/2) |n . L|

and they overlap iff ``min_L o(L) >= 0``. The least-overlap axis, pointed from
``a`` to ``b``, is the **contact normal**, and ``min_L o(L)`` the penetration
depth (the shortest translation that separates the boxes).

**Contact point**: the centroid of the intersection polygon ``a ∩ b``
(Sutherland–Hodgman clipping of ``b`` by the four half-planes of ``a``;
Sutherland & Hodgman, CACM 17(1), 1974). For a corner just entering an edge it
converges to the corner, for two faces pressed together to the middle of their
common stretch, and it is symmetric in ``a`` and ``b``. Where the intersection
has no area (touching) it is the middle of the touching points.

**Contact between two time steps** (:func:`swept_contact`): a loop that samples the boxes every
step finds them overlapping by up to a step's travel, and the least-overlap axis is then often
not the side they met on (a car hitting a standing box near its edge overlaps it more along the
road than across). The contact normal is instead the separating axis that closed last: of the
axes that separated the boxes at the previous step and no longer do, the one whose overlap
crossed zero latest, by linear interpolation ``f = o0 / (o0 - o1)`` (the separating-axis test for
moving boxes, Ericson §5.5.8, sampled at the two steps). When nothing separated them before (they
started overlapping), it is the least-overlap axis.

**Impact speed**: the closing speed of the two bodies' material points at the
contact point ``p`` along the normal ``N`` (rigid-body kinematics,
``v_p = v + ω × r`` with ``ω × r = ω (-r_y, r_x)`` in the plane)::

    v_n = ((v_a + ω_a × (p - c_a)) - (v_b + ω_b × (p - c_b))) . N

positive when the bodies approach. Velocities are over ground, in world axes.

:func:`overlaps_many` is the same test for one box against many, vectorised
with numpy (the hot path: one ego against every object, every plant step).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple, Sequence

import numpy as np

#: overlap tolerance (m): boxes closer than this to touching count as touching (rounding of poses)
TOUCH_TOL_M = 1e-9
#: an intersection thinner than this (m) has no area: touching boxes (their clipped overlap is a sliver)
_SLIVER_M = 1e-7


@dataclass(frozen=True, slots=True)
class Box:
    """An oriented rectangle: centre (m), heading (rad), length along the heading and width across (m)."""

    x_m: float
    y_m: float
    yaw_rad: float
    length_m: float
    width_m: float

    def __post_init__(self) -> None:
        if not (self.length_m >= 0.0 and self.width_m >= 0.0):
            raise ValueError(f"Box: expected length_m, width_m >= 0, got {self.length_m}, {self.width_m}")

    def axes(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """The unit axes ``u`` (along the heading) and ``n`` (to its left)."""
        c, s = math.cos(self.yaw_rad), math.sin(self.yaw_rad)
        return (c, s), (-s, c)

    def corners(self) -> np.ndarray:
        """The four corners, counter-clockwise from front-left: array of shape (4, 2) (m)."""
        (ux, uy), (nx, ny) = self.axes()
        hl, hw = self.length_m / 2.0, self.width_m / 2.0
        signs = ((1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0))
        return np.array([(self.x_m + a * hl * ux + b * hw * nx, self.y_m + a * hl * uy + b * hw * ny)
                         for a, b in signs])

    def moved(self, dx_m: float, dy_m: float, dyaw_rad: float = 0.0) -> Box:
        """The box translated by (dx, dy) and turned by ``dyaw_rad`` about its centre."""
        return Box(self.x_m + dx_m, self.y_m + dy_m, self.yaw_rad + dyaw_rad, self.length_m, self.width_m)


class BodyMotion(NamedTuple):
    """A body's velocity over ground in world axes (m/s) and its yaw rate (rad/s, counter-clockwise)."""

    vx_mps: float
    vy_mps: float
    yaw_rate_radps: float = 0.0


class Contact(NamedTuple):
    """Where two overlapping boxes touch: point (m), unit normal from the first box to the second, depth (m)."""

    x_m: float
    y_m: float
    normal_x: float
    normal_y: float
    depth_m: float


class _Frame(NamedTuple):
    """Half length, half width, cos and sin of the heading: floats for one box, arrays for many."""

    half_l: Any
    half_w: Any
    cos: Any
    sin: Any


def _frame(box: Box) -> _Frame:
    return _Frame(0.5 * box.length_m, 0.5 * box.width_m, math.cos(box.yaw_rad), math.sin(box.yaw_rad))


def _axis_overlaps(a: _Frame, b: _Frame, dx: Any, dy: Any) -> tuple[Any, Any, Any, Any]:
    """The overlaps ``o(L)`` on ``a``'s axes u, n and ``b``'s axes u, n (centre offset ``b - a`` = (dx, dy)).

    With ``C = |cos(yaw_b - yaw_a)|`` and ``S = |sin(yaw_b - yaw_a)|`` the projected radii of the module
    docstring become ``r_b(u_a) = l_b/2 C + w_b/2 S``, ``r_b(n_a) = l_b/2 S + w_b/2 C`` and alike for ``a``
    on ``b``'s axes. Only arithmetic and ``abs``: the same code serves floats (one pair) and numpy arrays
    (one box against many).
    """
    c = abs(a.cos * b.cos + a.sin * b.sin)
    s = abs(a.sin * b.cos - a.cos * b.sin)
    return (a.half_l + b.half_l * c + b.half_w * s - abs(dx * a.cos + dy * a.sin),
            a.half_w + b.half_l * s + b.half_w * c - abs(dy * a.cos - dx * a.sin),
            b.half_l + a.half_l * c + a.half_w * s - abs(dx * b.cos + dy * b.sin),
            b.half_w + a.half_l * s + a.half_w * c - abs(dy * b.cos - dx * b.sin))


def least_overlap(a: Box, b: Box) -> tuple[float, float, float]:
    """``(o, Lx, Ly)``: the least overlap ``o`` (m, negative: separated) over the four axes and its axis,
    pointed from ``a`` to ``b``. See the module docstring for the equation."""
    fa, fb = _frame(a), _frame(b)
    dx, dy = b.x_m - a.x_m, b.y_m - a.y_m
    o = _axis_overlaps(fa, fb, dx, dy)
    i = min(range(4), key=o.__getitem__)
    f = fa if i < 2 else fb
    lx, ly = (f.cos, f.sin) if i % 2 == 0 else (-f.sin, f.cos)
    return (o[i], lx, ly) if dx * lx + dy * ly >= 0.0 else (o[i], -lx, -ly)


def axis_overlaps(a: Box, b: Box) -> tuple[float, float, float, float]:
    """The overlaps ``o(L)`` (m, negative: separated along L) on ``a``'s axes u, n and ``b``'s axes u, n."""
    return _axis_overlaps(_frame(a), _frame(b), b.x_m - a.x_m, b.y_m - a.y_m)


def _axis(box: Box, i: int, toward: tuple[float, float]) -> tuple[float, float]:
    """Axis ``i`` (0: ``box``'s u, 1: its n) pointed along ``toward``."""
    c, s = math.cos(box.yaw_rad), math.sin(box.yaw_rad)
    lx, ly = (c, s) if i == 0 else (-s, c)
    return (lx, ly) if toward[0] * lx + toward[1] * ly >= 0.0 else (-lx, -ly)


def swept_contact(before: tuple[Box, Box], after: tuple[Box, Box]) -> Contact | None:
    """The contact of boxes ``after = (a, b)`` that were at ``before`` one step earlier, else None (apart).

    Normal from ``a`` to ``b``: the axis that separated them at ``before`` and closed last (module
    docstring); the point and depth as :func:`contact`'s.
    """
    hit = contact(*after)
    if hit is None:
        return None
    o0, o1 = axis_overlaps(*before), axis_overlaps(*after)
    closed = [(o0[i] / (o0[i] - o1[i]), i) for i in range(4) if o0[i] < 0.0 and o1[i] >= -TOUCH_TOL_M and o1[i] > o0[i]]
    if not closed:
        return hit
    i = max(closed)[1]
    a, b = after
    lx, ly = _axis(a if i < 2 else b, i % 2, (b.x_m - a.x_m, b.y_m - a.y_m))
    return Contact(hit.x_m, hit.y_m, lx, ly, max(o1[i], 0.0))


def overlaps(a: Box, b: Box, tol_m: float = TOUCH_TOL_M) -> bool:
    """Whether the boxes overlap or touch (separating-axis test)."""
    return least_overlap(a, b)[0] >= -tol_m


def overlaps_many(box: Box, others: np.ndarray, tol_m: float = TOUCH_TOL_M) -> np.ndarray:
    """Whether ``box`` overlaps each of ``others``, an array of shape (k, 5) of rows
    ``(x_m, y_m, yaw_rad, length_m, width_m)``: a bool array of shape (k,), the test of :func:`overlaps`.

    Bounding circles first (boxes whose centres are farther apart than the sum of their half diagonals
    cannot touch), then the four axes for the rest: most objects are far from the ego most of the time.
    """
    others = np.asarray(others, dtype=float).reshape(-1, 5)
    dx, dy = others[:, 0] - box.x_m, others[:, 1] - box.y_m
    reach = 0.5 * (math.hypot(box.length_m, box.width_m) + np.hypot(others[:, 3], others[:, 4])) + tol_m
    near = np.flatnonzero(dx * dx + dy * dy <= reach * reach)
    hit = np.zeros(len(others), dtype=bool)
    if len(near):
        rows = others[near]
        fb = _Frame(0.5 * rows[:, 3], 0.5 * rows[:, 4], np.cos(rows[:, 2]), np.sin(rows[:, 2]))
        o = _axis_overlaps(_frame(box), fb, dx[near], dy[near])
        hit[near] = np.minimum(np.minimum(o[0], o[1]), np.minimum(o[2], o[3])) >= -tol_m
    return hit


def _clip(polygon: list[tuple[float, float]], px: float, py: float, lx: float, ly: float,
          limit: float) -> list[tuple[float, float]]:
    """The part of ``polygon`` with ``(q - p) . L <= limit`` (one Sutherland–Hodgman pass)."""
    out: list[tuple[float, float]] = []
    n = len(polygon)
    for i in range(n):
        q0, q1 = polygon[i - 1], polygon[i]
        s0 = (q0[0] - px) * lx + (q0[1] - py) * ly - limit
        s1 = (q1[0] - px) * lx + (q1[1] - py) * ly - limit
        if (s0 <= 0.0) != (s1 <= 0.0):
            f = s0 / (s0 - s1)
            out.append((q0[0] + f * (q1[0] - q0[0]), q0[1] + f * (q1[1] - q0[1])))
        if s1 <= 0.0:
            out.append(q1)
    return out


def intersection_polygon(a: Box, b: Box) -> list[tuple[float, float]]:
    """The vertices of ``a ∩ b`` (counter-clockwise; degenerate when they only touch, empty when apart)."""
    polygon = [tuple(p) for p in b.corners().tolist()]
    (ux, uy), (nx, ny) = a.axes()
    tol = TOUCH_TOL_M
    for lx, ly, half in ((ux, uy, a.length_m / 2.0), (nx, ny, a.width_m / 2.0)):
        for sign in (1.0, -1.0):
            polygon = _clip(polygon, a.x_m, a.y_m, sign * lx, sign * ly, half + tol)
            if not polygon:
                return []
    return polygon


def _centroid(polygon: Sequence[tuple[float, float]]) -> tuple[float, float]:
    """Area centroid of a simple polygon; the middle of its extent when it has no area."""
    xs, ys = np.array(polygon).T
    cross = xs * np.roll(ys, -1) - np.roll(xs, -1) * ys
    area2 = cross.sum()
    span = max(np.ptp(xs), np.ptp(ys), 1e-3)
    if abs(area2) <= 2.0 * _SLIVER_M * span:  # thinner than a sliver: a segment or a point
        return 0.5 * (xs.min() + xs.max()), 0.5 * (ys.min() + ys.max())
    cx = ((xs + np.roll(xs, -1)) * cross).sum() / (3.0 * area2)
    cy = ((ys + np.roll(ys, -1)) * cross).sum() / (3.0 * area2)
    return float(cx), float(cy)


def contact(a: Box, b: Box, tol_m: float = TOUCH_TOL_M) -> Contact | None:
    """The contact of two boxes that overlap or touch, else None (see the module docstring)."""
    depth, lx, ly = least_overlap(a, b)
    if depth < -tol_m:
        return None
    polygon = intersection_polygon(a, b)
    if not polygon:  # touching within the tolerance, but clipped away by rounding: b's nearest corner
        corners = b.corners()
        polygon = [tuple(corners[np.argmin((corners - (a.x_m, a.y_m)) @ (lx, ly))])]
    x, y = _centroid(polygon)
    return Contact(float(x), float(y), lx, ly, max(depth, 0.0))


def point_velocity(box: Box, motion: BodyMotion, x_m: float, y_m: float) -> tuple[float, float]:
    """Velocity over ground (m/s) of the body's material point at (x, y): ``v + ω × (p - c)``."""
    rx, ry = x_m - box.x_m, y_m - box.y_m
    w = motion.yaw_rate_radps
    return motion.vx_mps - w * ry, motion.vy_mps + w * rx


def impact_speed_mps(hit: Contact, a: Box, a_motion: BodyMotion, b: Box, b_motion: BodyMotion) -> float:
    """Closing speed (m/s) of ``a`` and ``b`` at the contact point along the contact normal (from ``a`` to ``b``);
    positive when they approach. ``v_n = (v_a(p) - v_b(p)) . N``."""
    vax, vay = point_velocity(a, a_motion, hit.x_m, hit.y_m)
    vbx, vby = point_velocity(b, b_motion, hit.x_m, hit.y_m)
    return (vax - vbx) * hit.normal_x + (vay - vby) * hit.normal_y
