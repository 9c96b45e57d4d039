"""Evasive lane changes: the steering rows that end parallel to the road, one lane over (issue 22, rule 3).

The steering rows of :mod:`ecu.core.region.paths` hold their curvature until the car stops. At speed their
stopping paths are long (the friction circle leaves little braking beside the turn), so an arc that clears
an object close ahead keeps turning and leaves the road: in the ``emergency_steering`` catalogue no arc was
admissible where the offline oracle avoided by a lane change (``cosim.matrix.oracle``: late-stationary-free-80,
-100 and -120; cut-out-free-90 is avoided by braking since the release rule of :func:`ecu.core.planar.merged`). An emergency steering function of UN R79 does what the oracle does: it steers
around the object into the free lane and stays on the road (planar-protocol-facts.md section 4, S5).

**The rows** (``evasion_family``): for each side with a free lane, lateral offset ``W`` (:data:`EVASION_OFFSETS`:
from one lane width to the farthest the lane allows) and lateral level ``a_j`` (:data:`EVASION_LEVELS`), the
S-curve of two arcs ``+kappa_s`` and ``-kappa_s``, ``kappa_s = a_j / v_h^2``, each of the length ``l`` that
moves the car ``W`` over with its heading back to the road's::

    W = 2 (1 - cos(kappa_s l)) / kappa_s   ->   l = arccos(1 - kappa_s W / 2) / kappa_s

after the same lead-in as a steering row (hold, steering lag, half the ramp from ``kappa_0``), then on in the
new lane. The assumed road follows the current curvature ``kappa_0`` (:func:`ecu.core.planar.assumed_road`),
so the arcs are ``kappa_0 + kappa_s`` and ``kappa_0 - kappa_s`` and the lane after them ``kappa_0``. The switch
from ``+kappa_s`` to ``-kappa_s`` is a ramp replaced by its two halves at the end curvatures, as for the
lead-in (its heading change is kept exactly). A car dead ahead, reported by its nearest point, is widened by
its half width on each side (:mod:`ecu.core.region.objects`), so passing it takes most of a lane: hence the
offsets beyond the next lane's centre.

**Stopping along it**: the lead-in and the S at the hold speed ``v_h``, then full braking ``A`` straight on in
the new lane, ``s_stop = s_lead + 2 l + v_h^2 / (2 A)``. The execution (:mod:`ecu.core.lane_change_tracking`)
follows the same path by distance and brakes inside the friction circle along the S too, so it stops within
a part of this path: the boxes over the whole of it cover the car's.

**Lateral levels**: R79 gives no numeric lateral-acceleration cap for an ESF (planar-protocol-facts.md
section 4: none found; GRRF-82, Sep 2016, approved ESF with no objective test of its own). The arcs keep the
ACSF B1 bound, 3 m/s^2; the lane changes go from it to :data:`EVASION_FRICTION_SHARE` of the friction ``A``,
our choice: at 0.8 A the circle still leaves 0.6 A of braking. The rows are judged only when no arc is
disjoint (:mod:`ecu.core.region.decision`), so every decision an arc makes is unchanged.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from .paths import EgoState, PathSet, current_curvature, hold_phase, lead_in_m
from .params import GRAVITY_MPS2, RegionParams

#: lateral levels per side, evenly from the arcs' bound (ACSF B1, 3 m/s^2) to this share of the friction A
EVASION_LEVELS = 3
#: lateral offsets per side, evenly from one lane width (the next lane's centre) to the farthest the car's box
#: stays in that lane (half a lane beyond its centre, less half the car's width and the lateral margin)
EVASION_OFFSETS = 3
#: the lane changes' largest lateral acceleration as a share of the friction A (module docstring: our choice)
EVASION_FRICTION_SHARE = 0.8
#: boxes per lane-change stopping path: four times the arcs' 8. Each box covers the motion since the previous
#: one, so a box stretched over ``s_stop / M`` and turned by the S's heading ``psi`` is wider than the car by
#: about ``(s_stop / M) sin(psi) / 2`` each side. At 120 km/h ``s_stop`` is about 150 m and ``psi`` about 0.2
#: rad: 16 boxes (9.4 m) add 0.9 m each side, more than a lane change's margin to the road's edge and to the
#: object it passes; 32 boxes (4.7 m) add 0.47 m (measured: late-stationary-free-120 had no admissible
#: disjoint row with 16 boxes and had one with 32)
EVASION_SAMPLES_FACTOR = 4


@functools.lru_cache(maxsize=8)
def evasion_params(params: RegionParams) -> RegionParams:
    """``params`` with :data:`EVASION_SAMPLES_FACTOR` times the boxes per path."""
    return dataclasses.replace(params, path_samples=EVASION_SAMPLES_FACTOR * params.path_samples)


def evasion_rows(v_h: float, friction_mps2: float, lane_width_m: float, params: RegionParams,
                 sides: tuple[float, ...] = (1.0, -1.0)) -> tuple[np.ndarray, np.ndarray]:
    """(``kappa_s``, the lateral offset ``W``) per row, left positive: every side of ``sides`` (1: left, -1: right),
    offset and lateral level of the module docstring at ``v_h``, ``kappa_s`` capped by the steering-angle limit."""
    top = max(params.emergency_lat_accel_max_mps2, EVASION_FRICTION_SHARE * friction_mps2)
    levels = np.linspace(params.emergency_lat_accel_max_mps2, top, EVASION_LEVELS)
    limit = math.tan(params.steer_angle_max_rad) / params.wheelbase_m
    kappa = np.minimum(levels / max(v_h * v_h, 1e-9), limit)
    farthest = 1.5 * lane_width_m - 0.5 * params.width_m - params.lateral_margin_m
    offsets = np.linspace(lane_width_m, max(lane_width_m, farthest), EVASION_OFFSETS)
    k, w = (a.ravel() for a in np.meshgrid(kappa, offsets))
    return np.concatenate([side * k for side in sides]), np.concatenate([w for _ in sides])


def s_half_m(kappa_s: np.ndarray, offset_m: np.ndarray) -> np.ndarray:
    """``l`` per row: the arc length of each half of the S that moves the car ``offset_m`` over (module
    docstring); a curvature too tight for the offset (``kappa W / 2 > 1``) takes a half turn."""
    k = np.maximum(np.abs(kappa_s), 1e-12)
    return np.arccos(np.maximum(1.0 - 0.5 * k * offset_m, -1.0)) / k


def piecewise_poses(s: np.ndarray, lengths: np.ndarray, curvatures: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(position, heading) at arc lengths ``s`` ``(N, M)`` along rows of consecutive arcs: ``lengths`` and
    ``curvatures`` ``(N, P)`` (the last arc's length may be inf); an arc of length l is
    ``(exp(i kappa l) - 1) / (i kappa)``."""
    position = np.zeros(s.shape, dtype=complex)
    heading = np.ones(s.shape, dtype=complex)
    start = np.zeros(lengths.shape[0])
    for p in range(lengths.shape[1]):
        along = np.clip(s - start[:, None], 0.0, lengths[:, p:p + 1])
        k = curvatures[:, p:p + 1]
        k_safe = np.copysign(np.maximum(np.abs(k), 1e-12), k)
        turn = np.exp(1j * (k_safe * along))
        position = position + heading * ((turn - 1.0) / (1j * k_safe))
        heading = heading * turn
        start = start + lengths[:, p]
    return position, heading


def evasion_family(ego: EgoState, lane_width_m: float, params: RegionParams,
                   sides: tuple[float, ...] = (1.0, -1.0)) -> tuple[PathSet, np.ndarray, np.ndarray]:
    """The lane-change rows (module docstring) toward ``sides``, each row's lateral offset ``W`` (m, left positive)
    and lead-in (m)."""
    k0 = current_curvature(ego, params)
    friction = min(ego.decel_mps2, ego.friction_mu * GRAVITY_MPS2)
    d_hold, v_h = hold_phase(ego.speed_mps, ego.accel_mps2, params.hold_time_s)
    kappa, offset = evasion_rows(v_h, friction, lane_width_m, params, sides)
    half = s_half_m(kappa, offset)
    lead = lead_in_m(v_h, d_hold, k0, kappa, params)
    demand = np.abs(kappa) + abs(k0)
    feasible = demand * (v_h * v_h) < friction
    stop = lead + 2.0 * half + (v_h * v_h) / (2.0 * friction)
    n = kappa.size
    lengths = np.column_stack((lead, half, half, np.full(n, np.inf)))
    road = np.full(n, k0)
    curvatures = np.column_stack((road, road + kappa, road - kappa, road))
    position, heading = piecewise_poses(stop[:, None] * params.sample_fractions, lengths, curvatures)
    accel = np.full(n, ego.accel_mps2)
    return PathSet(kappa, demand, accel, np.full(n, d_hold), np.full(n, v_h), stop, feasible, position, heading,
                   friction), np.copysign(offset, kappa), lead
