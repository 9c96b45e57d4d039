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

* proximity ``p = clamp(1 - (range - standoff_m) / proximity_range_m, 0, 1)``,
  0 with no valid object: 0 beyond ``standoff + proximity_range``, 1 at the
  standoff itself. Linear in range because the DBC's ``Proximity`` must be
  explainable to a test driver, and range is what the stopping path consumes.
* nominal acceleration bounds ``[-peak_decel, driver_max_accel]``, contingency
  bounds ``[-D, -D]`` with ``D`` the model deceleration: the contingency
  *is* "brake at D".
* tightened bounds are the linear blend
  ``a_hi = (1 - p) * driver_max_accel + p * (-D)`` (and likewise
  ``a_lo = (1 - p) * (-peak_decel) + p * (-D)``, which is never applied: the
  ECU never lowers the driver's braking).
* ``a_hi`` reaches the car as ``ThrottleLimit = 100 % * clamp(a_hi /
  driver_max_accel, 0, 1)`` and, once ``a_hi < 0``, as a deceleration request
  ``-a_hi``. The disjointness check then uses ``min(a_drv, a_hi)``.

Rationale: the blend is the simplest monotone map from proximity to bounds
that equals the nominal bounds far away and the contingency bounds at the
standoff, so the car's allowed acceleration falls smoothly as it nears the
object instead of toggling between full throttle and full braking — the
adaptive damping the paper describes, which removes the energy that feeds the
reciprocal dance.
"""

from __future__ import annotations

from typing import NamedTuple

from .params import CoreParams

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


def proximity(object_valid: bool, range_m: float, params: CoreParams) -> float:
    """p = clamp(1 - (range - standoff) / proximity_range, 0, 1); 0 without an object."""
    if not object_valid:
        return 0.0
    p = 1.0 - (range_m - params.standoff_m) / params.proximity_range_m
    return min(1.0, max(0.0, p))


def tighten(p: float, params: CoreParams) -> Tightening:
    """Blend the nominal upper bound toward the contingency bound -D by proximity ``p``."""
    a_max = params.driver_max_accel_mps2
    a_hi = (1.0 - p) * a_max + p * (-params.model_decel_mps2)
    throttle_pct = FULL_THROTTLE_PCT * min(1.0, max(0.0, a_hi / a_max))
    return Tightening(p, a_hi, throttle_pct, max(0.0, -a_hi))


NO_TIGHTENING = Tightening(0.0, float("inf"), FULL_THROTTLE_PCT, 0.0)
