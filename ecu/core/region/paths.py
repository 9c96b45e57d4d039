"""The followable paths and the stopping path along each (Johnson 2019, Defs. 1 and 2).

Frame: the ego's rear axle at the origin, x forward, y left (ISO 8855); the kinematic single-track
model's rear axle follows the path without side slip (Rajamani 2012, section 2.2; CommonRoad's
kinematic model, S9), curvature ``kappa = tan(delta) / L``.

**The family** (rows of :class:`PathSet`, :data:`DRIVER`, :data:`NOMINAL`, :data:`LANE`, then the
steering rows):

* ``DRIVER``: the driver's commands held: the pedals' ``a`` for ``t_h``, the wheel's curvature ``kappa_d``
  (:func:`driver_curvature`) reached from the current ``kappa_0`` as an ECU path reaches its own (below),
  ``kappa_0`` throughout when the two agree; at a curve's entry the yaw rate lags the wheel by the
  steering's lag, and a path on ``kappa_0`` alone ran straight on across the oncoming lane;
* ``NOMINAL``: the same path at full throttle (the proximity of :mod:`ecu.core.proximity`);
* ``LANE``: braking along the road's curvature (the lane), reached as a steering row is;
* steering rows: ``kappa_j = a_j / v_h^2`` for lateral accelerations ``a_j`` evenly spaced over
  ``+-a_R79`` (``steer_paths`` levels); at low speed, where ``a_R79 / v_h^2`` exceeds the
  steering-angle limit ``tan(delta_max)/L``, the levels are spread evenly over that limit instead.

Each ECU path keeps ``kappa_0`` over a lead-in, then holds ``kappa_j``. The lead-in is the hold
(``t_h``), the steering lag ``tau`` and half the clothoid that ramps the curvature at
``kappa_dot = min(delta_dot_max / L, j_max / v_h^2)`` (the steering rate and the R79 jerk
target): ``s_lead = d_hold + v_h tau + v_h |kappa_j - kappa_0| / (2 kappa_dot)``. Replacing the
clothoid by its two halves at the end curvatures keeps its heading change exactly (our
approximation; its lateral error is below ``|dkappa| l^2 / 24`` over a ramp of length ``l``, a few mm).

**Stopping along a path** with the command ``a`` held for ``t_h`` and then braking inside the
friction circle ``a_x^2 + (v^2 kappa)^2 <= A^2`` (``A = min(D, mu g)``, D the strategy's model
deceleration). With ``u = v^2``, ``du/ds = -2 sqrt(A^2 - kappa^2 u^2)`` integrates to
``u(s) = (A/kappa) sin(phi_0 - 2 kappa s)``, ``sin(phi_0) = kappa v_h^2 / A`` (our derivation), so::

    d_hold = v t_h + a t_h^2 / 2      (v^2 / (-2a) if the car stops within the hold)
    s_brake = arcsin(kappa v_h^2 / A) / (2 kappa)   ->  v_h^2 / (2 A)  as kappa -> 0
    s_stop = d_hold + s_brake,  kappa = max(|kappa_0|, |kappa_j|)  (the larger demand: conservative)

With ``kappa = 0`` this is :func:`ecu.core.stopping_path.stopping_distance_m` term for term.
A path with ``kappa v_h^2 >= A`` is not followable (flag ``feasible``).

**Resolution**: ``path_samples`` poses per path at ``s_k = s_stop k / M``; :mod:`ecu.core.region.overlap`
covers the motion between two poses with a stretched box.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..stopping_path import stopping_distance_m
from .params import GRAVITY_MPS2, RegionParams

DRIVER, NOMINAL, LANE, FIRST_STEER = 0, 1, 2, 3


class EgoState(NamedTuple):
    """The ego this cycle (SI; yaw rate and wheel angle positive turning left)."""

    speed_mps: float
    accel_mps2: float
    decel_mps2: float
    yaw_rate_radps: float = 0.0
    road_wheel_angle_rad: float = 0.0
    friction_mu: float = 1.0


class PathSet(NamedTuple):
    """The family's rows (shape ``(N,)``) and their sampled poses (shape ``(N, M)``, rear axle, complex:
    position ``x + iy`` and heading ``cos(psi) + i sin(psi)``)."""

    curvature_1pm: np.ndarray
    #: the largest |curvature| along each path: max(|kappa_0|, |kappa_j|)
    max_curvature_1pm: np.ndarray
    accel_mps2: np.ndarray
    hold_m: np.ndarray
    hold_speed_mps: np.ndarray
    stop_m: np.ndarray
    feasible: np.ndarray
    position: np.ndarray
    heading: np.ndarray
    friction_mps2: float


def current_curvature(ego: EgoState, params: RegionParams) -> float:
    """kappa_0 = r / v above ``yaw_rate_min_speed_mps`` (measured), else tan(delta) / L (kinematic)."""
    if ego.speed_mps > params.yaw_rate_min_speed_mps:
        return ego.yaw_rate_radps / ego.speed_mps
    return math.tan(ego.road_wheel_angle_rad) / params.wheelbase_m


def hold_phase(speed_mps: float, accel_mps2: float, hold_s: float) -> tuple[float, float]:
    """(d_hold, v_h), as :func:`ecu.core.stopping_path.stopping_distance_m` (``v_h = 0``: stopped in the hold)."""
    v = max(0.0, speed_mps)
    v_h = v + accel_mps2 * hold_s
    if v_h < 0.0:
        return v * v / (-2.0 * accel_mps2), 0.0
    return v * hold_s + 0.5 * accel_mps2 * hold_s * hold_s, v_h


def driver_curvature(ego: EgoState, params: RegionParams) -> float:
    """kappa_d = tan(delta) / L, the curvature the driver's wheel commands: the kinematic single-track model's, and
    the steady state of the dynamic one when it steers neutrally (axle cornering stiffnesses proportional to the
    axle loads, ``C_i = mu C_S F_z,i`` as CommonRoad's vehicle models take them, S9: the understeer gradient
    ``m/L (l_r/C_f - l_f/C_r)`` is then 0)."""
    return math.tan(ego.road_wheel_angle_rad) / params.wheelbase_m


def curvature_rows(kd: float, v_h: float, road_curvature_1pm: float, params: RegionParams,
                   base: bool, steering: bool) -> np.ndarray:
    """The rows' curvatures: (``base``) driver and nominal (``kd``, the driver's), lane, then (``steering``) the
    levels ``a_j / v_h^2``."""
    limit = math.tan(params.steer_angle_max_rad) / params.wheelbase_m
    scale = min(1.0 / max(v_h * v_h, 1e-9), limit / params.emergency_lat_accel_max_mps2)
    first = FIRST_STEER if base else 0
    kappa = np.empty(first + (params.steer_paths if steering else 0))
    if base:
        kappa[:FIRST_STEER] = kd, kd, road_curvature_1pm
    if steering:
        np.multiply(params.lateral_levels_mps2, scale, out=kappa[first:])
    return kappa


def braking_m(v_h: np.ndarray, kappa: np.ndarray, friction_mps2: float) -> tuple[np.ndarray, np.ndarray]:
    """(s_brake, feasible): ``arcsin(kappa v_h^2 / A) / (2 kappa)`` per row (``kappa`` >= 0; 0 is taken
    as 1e-12 1/m, whose result is ``v_h^2 / (2A)`` to 1e-16)."""
    k = np.maximum(kappa, 1e-12)
    q = k * (v_h * v_h) / friction_mps2
    return np.arcsin(np.minimum(q, 1.0)) / (2.0 * k), q < 1.0


def lead_in_m(v_h: float, d_hold: float, k0: float, kappa: np.ndarray, params: RegionParams) -> np.ndarray:
    """s_lead = d_hold + v_h tau + v_h |kappa - kappa_0| / (2 kappa_dot)."""
    rate = min(params.steer_rate_max_radps / params.wheelbase_m,
               params.emergency_lat_jerk_max_mps3 / max(v_h * v_h, 1e-9))
    return (d_hold + v_h * params.steer_lag_s) + (v_h / (2.0 * rate)) * np.abs(kappa - k0)


def sample_poses(stop_m: np.ndarray, lead_m: np.ndarray, k0: float, kappa: np.ndarray,
                 fractions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(position, heading) of the rear axle at ``s_k = s_stop k / M``: an arc of ``kappa_0`` over the
    lead-in composed with an arc of the row's curvature; an arc of length l is
    ``z(l) = (exp(i kappa l) - 1) / (i kappa)`` (``l`` for kappa = 0)."""
    s = stop_m[:, None] * fractions
    l1 = np.minimum(s, lead_m[:, None])
    k = np.copysign(np.maximum(np.abs(kappa), 1e-12), kappa)[:, None]
    turn2 = np.exp(1j * (k * (s - l1)))
    z2 = (turn2 - 1.0) / (1j * k)
    if k0 == 0.0:
        return l1 + z2, turn2
    turn1 = np.exp(1j * (k0 * l1))
    return (turn1 - 1.0) / (1j * k0) + turn1 * z2, turn1 * turn2


def _driver_rows(ego: EgoState, t_h: float, rows: tuple[np.ndarray, ...], curvatures: tuple[float, float],
                 params: RegionParams) -> None:
    """Set the nominal row's full throttle and the driver's rows' lead-in: ``kappa_0`` throughout when the wheel
    commands it (``curvatures``: kappa_0, kappa_d), else the lead-in of :func:`lead_in_m` from the row's own hold."""
    hold, speed, accel, lead = rows
    hold[NOMINAL], speed[NOMINAL] = hold_phase(ego.speed_mps, params.driver_max_accel_mps2, t_h)
    accel[NOMINAL] = params.driver_max_accel_mps2
    k0, kd = curvatures
    if kd == k0:
        lead[DRIVER] = lead[NOMINAL] = np.inf
    else:
        lead[NOMINAL] = lead_in_m(float(speed[NOMINAL]), float(hold[NOMINAL]), k0, np.array([kd]), params)[0]


def path_family(ego: EgoState, road_curvature_1pm: float, params: RegionParams, base: bool = True,
                steering: bool = True) -> PathSet:
    """The rows of the module docstring, sampled: (``base``) the driver's, nominal and lane rows, (``steering``)
    the steering rows (:mod:`ecu.core.region.decision` chooses which, and when)."""
    k0 = current_curvature(ego, params)
    kd = driver_curvature(ego, params) if ego.speed_mps > params.yaw_rate_min_speed_mps else k0
    t_h, friction = params.hold_time_s, min(ego.decel_mps2, ego.friction_mu * GRAVITY_MPS2)
    d_hold, v_h = hold_phase(ego.speed_mps, ego.accel_mps2, t_h)
    kappa = curvature_rows(kd, v_h, road_curvature_1pm, params, base, steering)
    hold, speed, accel = rows = np.empty((3, kappa.size))
    rows.T[...] = d_hold, v_h, ego.accel_mps2  # one fill for the three (np.full's Python wrapper costs a call each)
    lead = lead_in_m(v_h, d_hold, k0, kappa, params)
    if base:
        _driver_rows(ego, t_h, (hold, speed, accel, lead), (k0, kd), params)
    demand = np.maximum(np.abs(kappa), abs(k0))
    brake, feasible = braking_m(speed, demand, friction)
    stop = hold + brake
    if base and k0 == 0.0 and kd == 0.0:  # the straight driver's rows: the 1-D core's own stopping distance
        stop[DRIVER] = stopping_distance_m(ego.speed_mps, ego.accel_mps2, t_h, friction)
        stop[NOMINAL] = stopping_distance_m(ego.speed_mps, params.driver_max_accel_mps2, t_h, friction)
    position, heading = sample_poses(stop, lead, k0, kappa, params.sample_fractions)
    return PathSet(kappa, demand, accel, hold, speed, stop, feasible, position, heading, friction)
