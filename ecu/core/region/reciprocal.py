"""The reciprocal split of ORCA for cars that keep their paths: which side of the avoidance is ours.

ORCA (van den Berg, Guy, Lin and Manocha, "Reciprocal n-Body Collision Avoidance", ISRR 2009, Springer
STAR 70, 2011; planar-protocol-facts.md §8) gives each of two agents half of the responsibility for
avoiding each other. With ``p`` the other's position relative to ours, ``v = v_A - v_B`` our relative
velocity, ``r`` the sum of the two radii and ``tau`` the time horizon, the truncated velocity obstacle is
``VO = {v : |t v - p| < r for some t in (0, tau]}``: a cone from the origin tangent to the disc ``(p, r)``,
cut off by the disc ``(p / tau, r / tau)``. ``u`` is the smallest change of ``v`` to its boundary and ``n``
the boundary's outward normal there; agent A keeps to ``{v'_A : (v'_A - (v_A + u / 2)) . n >= 0}``.

The closest boundary point (our own derivation from these definitions): with ``w = v - p / tau``, it lies on
the cut-off circle when ``w . p < 0`` and ``(w . p)^2 > r^2 |w|^2`` (``n = w / |w|``); otherwise on the leg on
``w``'s side of ``p`` (left when ``det(p, w) > 0``), a ray from the origin at angle ``+-asin(r / |p|)`` from
``p``, whose outward normal is the leg direction turned a right angle away from the cone.

A car keeps its path, so its velocity is ``s e`` (``e`` its heading; ``e = (1, 0)`` in the ego frame) and the
constraint reads ``s n_x >= (v_A + u/2) . n``. When ``n_x < 0`` it bounds our speed from above: our half of the
avoidance is to slow, and the way-out rule ``reciprocal`` tightens against that car. When ``n_x > 0`` our half
is to go on (the other slows): we do not tighten against it, and the contingency keeps our stopping path
disjoint from its stopping region as always. A tie (``det(p, w) = 0``, the symmetric crossing) takes the right
leg, for both cars alike: the convention of passing on the same side, which is what breaks the symmetry.
"""

from __future__ import annotations

import math
from typing import Sequence

import numpy as np

from .objects import TrackBox
from .params import CAPABILITIES, RegionParams

#: ORCA's time horizon tau (s): a crossing car further than this in time is not yet shared out
HORIZON_S = 5.0


def outward_normal(p: tuple[float, float], v: tuple[float, float], r: float, tau: float) -> tuple[float, float]:
    """``n`` of the module docstring for relative position ``p``, relative velocity ``v``, radius ``r``."""
    px, py = p
    dist_sq = px * px + py * py
    if dist_sq <= r * r:  # already overlapping: away from the other
        d = math.sqrt(dist_sq) or 1.0
        return -px / d, -py / d
    wx, wy = v[0] - px / tau, v[1] - py / tau
    dot = wx * px + wy * py
    if dot < 0.0 and dot * dot > r * r * (wx * wx + wy * wy):
        w = math.hypot(wx, wy) or 1.0
        return wx / w, wy / w
    leg = math.sqrt(dist_sq - r * r)
    if px * wy - py * wx > 0.0:  # left leg: direction p turned by +asin(r/|p|), normal to its left
        dx, dy = (px * leg - py * r) / dist_sq, (px * r + py * leg) / dist_sq
        return -dy, dx
    dx, dy = (px * leg + py * r) / dist_sq, (-px * r + py * leg) / dist_sq  # right leg, normal to its right
    return dy, -dx


def ours_to_slow(track: TrackBox, ego_speed_mps: float, params: RegionParams) -> bool:
    """Whether ORCA's split gives us the slowing half against ``track`` (module docstring)."""
    length = CAPABILITIES.get(track.size_class, CAPABILITIES[0]).length_m
    px, py = track.x_m + 0.5 * params.length_m, track.y_m  # from our box's centre to its nearest point
    d = math.hypot(px, py) or 1.0
    px, py = px + 0.5 * length * px / d, py + 0.5 * length * py / d  # ... and on to its centre
    nx, _ = outward_normal((px, py), (-track.vx_mps, -track.vy_mps), 0.5 * (params.length_m + length), HORIZON_S)
    return nx < 0.0


def reciprocal_mask(tracks: Sequence[TrackBox], ego_speed_mps: float, params: RegionParams) -> np.ndarray:
    """Per track: ORCA gives us the slowing half against it."""
    return np.array([ours_to_slow(t, ego_speed_mps, params) for t in tracks], dtype=bool)
