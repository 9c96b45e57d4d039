"""Driver intent, proximity and constraint tightening (the paper's three strategies).

Driver intent (a simple documented model): the pedals map linearly to an
intended acceleration::

    a_drv = accel_pedal * driver_max_accel_mps2 - brake_pedal * peak_decel_mps2

with pedals as fractions 0..1 (a fully pressed brake pedal asks for peak
deceleration). The brake term means the ECU sees the driver's own braking
and never plans to lower it.

Strategies: ``none`` and ``conservative`` differ only in the model
deceleration fraction (0.9 and 0.8). ``tightening`` uses 0.9 plus constraint
tightening, formalised below.

Constraint tightening — *our formalisation*. The paper (section II-D) says
only that the nominal constraint bounds move toward the contingency bounds
"with respect to some notion of proximity". We take:

* proximity is closeness to the *contingency boundary*, measured as the
  stopping-path margin under the nominal command::

      m = range - standoff_m - d(v, driver_max_accel)       (m)
      p = clamp(1 - m / proximity_margin_m, 0, 1)

  where ``d`` is the stopping distance of :mod:`ecu.core.stopping_path`
  (hold full throttle for ``t_h``, then brake at ``D``) and ``v`` the closing
  speed. ``p = 0`` while at least ``proximity_margin_m`` separates the nominal
  stopping path from the standoff, ``p = 1`` when the nominal command would
  itself violate disjointness. No valid object: ``p = 0``.
* nominal acceleration bounds ``[-peak_decel, driver_max_accel]``; the
  contingency's bounds are its own command, full braking
  ``[-C, -C]`` with ``C = contingency_decel_mps2`` (the contingency
  constraints "most quickly bring the agent to a stop", paper II-D).
* tightened bounds are the linear blend
  ``a_hi = (1 - p) * driver_max_accel + p * (-C)`` (and likewise
  ``a_lo = (1 - p) * (-peak_decel) + p * (-C)``, which is never applied: the
  ECU never lowers the driver's braking).
* ``a_hi`` reaches the car as ``ThrottleLimit = 100 % * clamp(a_hi /
  driver_max_accel, 0, 1)`` and, once ``a_hi < 0``, as a deceleration request
  ``-a_hi``. The disjointness check then uses ``min(a_drv, a_hi)``.

Rationale: the blend is the simplest monotone map from proximity to bounds
that equals the nominal bounds far from the boundary and the contingency
bounds on it, so the car's allowed acceleration falls smoothly as the
stopping path nears the object instead of toggling between full throttle and
full braking — the adaptive damping the paper describes, which removes the
energy that feeds the reciprocal dance. Measuring proximity as the margin to
the boundary (not the raw range) keeps the full dynamic range while the car
is far from needing to brake, whatever its speed, and makes the car ride a
speed-independent distance ``(1 - p*) * proximity_margin_m`` inside the
boundary, with ``p*`` the proximity at which ``a_hi`` equals the deceleration
the approach needs; that distance matters most at low speed, where the
constant-deceleration model's error from the actuation lags is largest.
An earlier formalisation (proximity linear in range over 40 m, blending toward
``-D``) asked for too little braking to keep the car off the boundary and
collided in the paper scenario.
"""

from __future__ import annotations

from typing import NamedTuple

from .params import CoreParams
from .stopping_path import stopping_distance_m

FULL_THROTTLE_PCT = 100.0


class Tightening(NamedTuple):
    """The tightened upper bound and how it reaches the car (immutable)."""

    proximity: float
    accel_upper_mps2: float
    throttle_limit_pct: float
    decel_request_mps2: float

    @property
    def restricts(self) -> bool:
        return self.throttle_limit_pct < FULL_THROTTLE_PCT or self.decel_request_mps2 > 0.0


def driver_accel_mps2(accel_pedal: float, brake_pedal: float, params: CoreParams) -> float:
    """Intended acceleration (m/s^2) from pedal fractions 0..1."""
    return accel_pedal * params.driver_max_accel_mps2 - brake_pedal * params.peak_decel_mps2


def proximity(object_valid: bool, range_m: float, closing_speed_mps: float, params: CoreParams,
              decel_mps2: float | None = None) -> float:
    """p = clamp(1 - m / proximity_margin_m, 0, 1), m the nominal stopping-path margin (m); 0 without an object.

    ``decel_mps2`` overrides the model deceleration D (the ``adaptive`` strategy's estimate).
    """
    if not object_valid:
        return 0.0
    nominal_m = stopping_distance_m(closing_speed_mps, params.driver_max_accel_mps2, params.hold_time_s,
                                    params.model_decel_mps2 if decel_mps2 is None else decel_mps2)
    margin_m = range_m - params.standoff_m - nominal_m
    p = 1.0 - margin_m / params.proximity_margin_m
    return min(1.0, max(0.0, p))


def tighten(p: float, params: CoreParams) -> Tightening:
    """Blend the nominal upper bound toward the contingency bound -C by proximity ``p``."""
    a_max = params.driver_max_accel_mps2
    a_hi = (1.0 - p) * a_max + p * (-params.contingency_decel_mps2)
    throttle_pct = FULL_THROTTLE_PCT * min(1.0, max(0.0, a_hi / a_max))
    return Tightening(p, a_hi, throttle_pct, max(0.0, -a_hi))


NO_TIGHTENING = Tightening(0.0, float("inf"), FULL_THROTTLE_PCT, 0.0)
