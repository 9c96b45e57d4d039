"""Proximity to the contingency boundary, behind a stationary or oncoming object.

The paper (Johnson 2019, section II-D) moves the nominal constraint bounds
toward the contingency's "with respect to some notion of proximity". *Our
formalisation*: proximity is closeness to the contingency boundary, measured
as the stopping-path margin under the nominal command (full throttle)::

    m = range - standoff_m - d(v, driver_max_accel)       (m)
    p = clamp(1 - m / proximity_margin_m, 0, 1)

where ``d`` is the stopping distance of :mod:`ecu.core.stopping_path` (hold
full throttle for ``t_h``, then brake at ``D``) and ``v`` our speed. ``p = 0``
while at least ``proximity_margin_m`` separates the nominal stopping path
from the standoff, ``p = 1`` when the nominal command would itself violate
disjointness. No valid object in our path: ``p = 0``. Behind a moving object
the margin is a time at the closing speed
(:func:`ecu.core.relative_stop.moving_proximity`).

Measuring proximity as the margin to the boundary (not the raw range) keeps
the full dynamic range while the car is far from needing to brake, whatever
its speed. Every strategy computes it (``EcuStatus.Proximity``); the ones that
tighten act on it (:mod:`ecu.core.strategies.tightening`).
"""

from __future__ import annotations

from .params import CoreParams
from .stopping_path import stopping_distance_m


def proximity(object_valid: bool, range_m: float, speed_mps: float, params: CoreParams,
              decel_mps2: float | None = None) -> float:
    """p = clamp(1 - m / proximity_margin_m, 0, 1), m the nominal stopping-path margin (m); 0 without an object.

    ``speed_mps``: the speed that must reach zero (negative counts as 0); ``decel_mps2``: the model
    deceleration D of this cycle (None: the strategy's fixed ``model_decel_mps2``).
    """
    if not object_valid:
        return 0.0
    decel = params.model_decel_mps2 if decel_mps2 is None else decel_mps2
    nominal_m = stopping_distance_m(speed_mps, params.driver_max_accel_mps2, params.hold_time_s, decel)
    margin_m = range_m - params.standoff_m - nominal_m
    p = 1.0 - margin_m / params.proximity_margin_m
    return min(1.0, max(0.0, p))
