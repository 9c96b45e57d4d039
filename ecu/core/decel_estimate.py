"""Online estimate of the achievable deceleration, for the ``adaptive`` strategy (our extension).

Why: the paper's strategies brake by a fixed model deceleration
``D = fraction * peak_decel_mps2`` with the peak measured on a dry road. On a
wetter road the car cannot brake that hard and every strategy collides
(README, sensitivity table). Production AEB functions adapt to the road: the
brake system knows when the tyres are at their friction limit, because ABS
is then regulating the wheel slip (Bosch *Automotive Handbook*, ABS chapter:
ABS holds the braking slip near the peak of the mu-slip curve, about
0.1-0.3), and the deceleration the car then achieves *is* the achievable
deceleration. This module turns that into an estimate ``a_hat`` (m/s^2).

Evidence, each cycle with valid wheel speeds and an estimated speed of at
least ``decel_estimate_min_speed_mps`` (below it slip ratios and derivatives
mean little):

* measured deceleration ``a_m``: the reference speed's derivative through a
  first-order filter (``tau_f = decel_filter_time_constant_s``)::

      a_m[k] = a_m[k-1] + (dt / tau_f) * ((v[k-1] - v[k]) / dt - a_m[k-1])

* **braking** (our last request or the driver's pedal x peak, ``R > 0``) that
  has lasted ``decel_settle_cycles`` (the brake's dead time plus its
  build-up) is *at the road's limit* when ABS is regulating, i.e. the braking
  slip ``s_i = (v - w_i) / v`` of some wheel has been at or above
  ``abs_slip_threshold`` for ``abs_slip_cycles`` cycles (a debounce against
  noisy wheel speeds), or when the car falls short of the request,
  ``R - a_m >= decel_shortfall_mps2``. The evidence is ``a_m``; below the
  limit ``a_m`` only counts when it exceeds the estimate (a lower bound);
* **traction**: not braking, the driven wheels spin at least
  ``abs_slip_threshold`` faster than the reference for ``decel_settle_cycles``.
  The driven axle then transmits ``mu * g * share * m``, so the road allows
  about ``-a_m / driven_axle_load_share`` of braking on all four wheels (the
  static share; the load moves off the front axle while accelerating, so this
  errs low, on the safe side).

Update (first-order, ``tau_e = decel_estimate_time_constant_s``)::

    a_hat += (dt / tau_e) * (evidence - a_hat)

then ``a_hat`` is clamped to ``[decel_estimate_floor_mps2, peak_decel_mps2]``:
it **never exceeds the configured peak**. Before any evidence it is the
documented prior ``a_hat = peak_decel_mps2`` (the dry-road value: with no
evidence ``adaptive`` plans exactly like ``tightening``). Invalid wheel
speeds leave the estimate unchanged (no evidence from invalid data); starting
to brake still needs valid inputs (:mod:`ecu.core.modes`).

Known limits: a car that neither spins its driven wheels nor brakes hard
keeps the dry prior, so a slippery road met at constant speed is discovered
only by the first hard braking. An ESC friction estimate on CAN is not used.

Pure functions; the state is the :class:`DecelEstimate` record carried in
:class:`ecu.core.types.CoreState`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from .params import DRIVEN_WHEELS, CoreParams


class DecelEstimate(NamedTuple):
    """Estimator state (m/s^2 and cycles)."""

    #: the estimate of the achievable deceleration; ``inf`` = no evidence yet (the prior applies).
    achievable_mps2: float = math.inf
    #: filtered measured deceleration.
    measured_mps2: float = 0.0
    #: consecutive cycles with braking commanded (saturates).
    braking_cycles: int = 0
    #: consecutive braking cycles with slip at or above the ABS threshold (saturates).
    slip_cycles: int = 0


def achievable_decel_mps2(estimate: DecelEstimate, params: CoreParams) -> float:
    """The estimate in use: the prior ``peak_decel_mps2`` before evidence, never above it."""
    return min(estimate.achievable_mps2, params.peak_decel_mps2)


def max_slip(speed_mps: float, wheels_mps: tuple[float, ...]) -> float:
    """Largest braking slip ``(v - w_i) / v`` over the wheels (0 for ``v <= 0``)."""
    if speed_mps <= 0.0:
        return 0.0
    return (speed_mps - min(wheels_mps)) / speed_mps


def traction_slip(speed_mps: float, wheels_mps: tuple[float, ...], params: CoreParams) -> float:
    """Traction slip ``(min driven wheel - v) / v`` (0 for ``v <= 0`` or all-wheel drive)."""
    driven = DRIVEN_WHEELS[params.driven_axle]
    if speed_mps <= 0.0 or not driven:
        return 0.0
    return (min(map(wheels_mps.__getitem__, driven)) - speed_mps) / speed_mps


def at_limit(estimate: DecelEstimate, request_mps2: float, params: CoreParams) -> bool:
    """Whether the settled braking is limited by the road: ABS slip, or the car falls short of the request."""
    if estimate.braking_cycles < params.decel_settle_cycles:
        return False
    abs_active = estimate.slip_cycles >= params.abs_slip_cycles
    return abs_active or request_mps2 - estimate.measured_mps2 >= params.decel_shortfall_mps2


def update(estimate: DecelEstimate, prev_speed_mps: float, speed_mps: float,
           wheels_mps: tuple[float, ...], request_mps2: float, params: CoreParams) -> DecelEstimate:
    """One cycle with *valid* wheel speeds (the caller skips invalid cycles).

    ``request_mps2`` is the deceleration braking was commanded at last cycle (ours or the
    driver's pedal x peak; 0 = not braking).
    """
    dt = params.cycle_s
    raw_mps2 = (prev_speed_mps - speed_mps) / dt
    measured = estimate.measured_mps2 + min(1.0, dt / params.decel_filter_time_constant_s) * (
        raw_mps2 - estimate.measured_mps2)
    braking = request_mps2 > 0.0
    braking_cycles = min(estimate.braking_cycles + 1, 1_000_000) if braking else 0
    slipping = braking and max_slip(speed_mps, wheels_mps) >= params.abs_slip_threshold
    slip_cycles = min(estimate.slip_cycles + 1, 1_000_000) if slipping else 0
    if not braking:
        spinning = traction_slip(speed_mps, wheels_mps, params) >= params.abs_slip_threshold
        slip_cycles = min(estimate.slip_cycles + 1, 1_000_000) if spinning else 0
    nxt = DecelEstimate(estimate.achievable_mps2, measured, braking_cycles, slip_cycles)
    current = achievable_decel_mps2(estimate, params)
    if speed_mps < params.decel_estimate_min_speed_mps:
        return nxt
    if braking:
        evidence = measured
        use = braking_cycles >= params.decel_settle_cycles and (
            at_limit(nxt, request_mps2, params) or measured > current)
    else:  # the driven axle at its traction limit: mu*g ~ accel / load share
        evidence = -measured / params.driven_axle_load_share
        use = slip_cycles >= params.decel_settle_cycles
    if use:
        current += min(1.0, dt / params.decel_estimate_time_constant_s) * (evidence - current)
    clamped = min(params.peak_decel_mps2, max(params.decel_estimate_floor_mps2, current))
    return nxt._replace(achievable_mps2=clamped)
