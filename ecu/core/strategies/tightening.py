"""``tightening`` (Johnson 2019, section III): plans with 0.9 of the peak and tightens the driver's bound.

Constraint tightening, *our formalisation*. The paper (section II-D) says
only that the nominal constraint bounds move toward the contingency bounds
"with respect to some notion of proximity". We take:

* proximity ``p`` in 0..1, closeness to the contingency boundary
  (:mod:`ecu.core.proximity`; behind a moving object,
  :func:`ecu.core.relative_stop.moving_proximity`);
* nominal acceleration bounds ``[-peak_decel, driver_max_accel]``; the
  contingency's bounds are its own command, full braking
  ``[-C, -C]`` with ``C = contingency_decel_mps2`` (the contingency
  constraints "most quickly bring the agent to a stop", paper II-D);
* tightened bounds are the linear blend
  ``a_hi = (1 - p) * driver_max_accel + p * (-C)`` (and likewise
  ``a_lo = (1 - p) * (-peak_decel) + p * (-C)``, which is never applied: the
  ECU never lowers the driver's braking);
* ``a_hi`` reaches the car as ``ThrottleLimit = 100 % * clamp(a_hi /
  driver_max_accel, 0, 1)`` and, once ``a_hi < 0``, as a deceleration request
  ``-a_hi``. The disjointness check then uses ``min(a_drv, a_hi)``.

Rationale: the blend is the simplest monotone map from proximity to bounds
that equals the nominal bounds far from the boundary and the contingency
bounds on it, so the car's allowed acceleration falls smoothly as the
stopping path nears the object instead of toggling between full throttle and
full braking — the adaptive damping the paper describes, which removes the
energy that feeds the reciprocal dance. With proximity measured as the margin
to the boundary the car rides a speed-independent distance
``(1 - p*) * proximity_margin_m`` inside the boundary, with ``p*`` the
proximity at which ``a_hi`` equals the deceleration the approach needs; that
distance matters most at low speed, where the constant-deceleration model's
error from the actuation lags is largest. An earlier formalisation (proximity
linear in range over 40 m, blending toward ``-D``) asked for too little
braking to keep the car off the boundary and collided in the paper scenario.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..strategy import FULL_THROTTLE_PCT, FixedDeceleration, Tightening

if TYPE_CHECKING:
    from ..params import CoreParams


def tighten(p: float, params: CoreParams) -> Tightening:
    """Blend the nominal upper bound toward the contingency bound -C by proximity ``p``:
    ``a_hi = (1 - p) a_max + p (-C)``, throttle ``100 % clamp(a_hi / a_max, 0, 1)``, request ``max(0, -a_hi)``."""
    a_max = params.driver_max_accel_mps2
    a_hi = (1.0 - p) * a_max + p * (-params.contingency_decel_mps2)
    throttle_pct = FULL_THROTTLE_PCT * min(1.0, max(0.0, a_hi / a_max))
    request_mps2 = max(0.0, -a_hi)
    return Tightening(p, a_hi, throttle_pct, request_mps2, throttle_pct < FULL_THROTTLE_PCT or request_mps2 > 0.0)


class ConstraintTightening(FixedDeceleration):
    """D = ``tightening_decel_fraction`` x peak (0.9), and the bound of :func:`tighten`."""

    def decel_fraction(self, params: CoreParams) -> float:
        return params.tightening_decel_fraction

    def tighten(self, proximity: float, params: CoreParams) -> Tightening:
        return tighten(proximity, params)


STRATEGY = ConstraintTightening()
