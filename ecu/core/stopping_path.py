"""Stopping path under a constant-deceleration model, and the disjointness check.

Selective determinism (Johnson 2019, Def. 1 and Property 1): each cycle the
ECU asks whether the driver's command, held for one more cycle, still leaves
a stopping path that ends at least ``standoff_m`` before the object.

Model. The command ``a`` (m/s^2) is held for the hold time
``t_h = cycle_s + actuation_latency_s`` (our own cycle plus the declared
actuation latency), then the car brakes at the model deceleration
``D = model_decel_fraction * peak_decel_mps2``::

    v_h = max(0, v + a * t_h)
    d_hold = v * t_h + a * t_h^2 / 2        if v + a * t_h >= 0
           = v^2 / (-2 a)                    otherwise (stopped during the hold)
    d = d_hold + v_h^2 / (2 D)

Object. With range ``r`` and range rate ``r_dot`` (negative closing), the
object's own speed along our path is ``v_obj = v_ego + r_dot``. For a moving
object (``v_obj > moving_object_speed_mps``) "stop" means zero *relative*
speed (the paper's footnote 1 allows either): ``v`` is replaced by the closing
speed ``v_rel = max(0, -r_dot)`` and, for a constant-speed object,
``a_rel = a`` (:mod:`ecu.core.relative_stop`, which the planner uses there).
Otherwise (stationary or oncoming) "stop" means zero absolute speed with
``v = v_ego``; an oncoming object's own stopping region is that agent's own
responsibility under selective determinism.

Disjoint iff ``d + standoff_m <= r``. No valid object: disjoint.
"""

from __future__ import annotations

from .params import CoreParams


def stopping_distance_m(speed_mps: float, accel_mps2: float, hold_s: float, decel_mps2: float) -> float:
    """Distance (m) to stop from ``speed_mps`` holding ``accel_mps2`` for ``hold_s`` then braking at ``decel_mps2``."""
    v = max(0.0, speed_mps)
    v_h = v + accel_mps2 * hold_s
    if v_h < 0.0:
        return v * v / (-2.0 * accel_mps2)
    return v * hold_s + 0.5 * accel_mps2 * hold_s * hold_s + v_h * v_h / (2.0 * decel_mps2)


def closing_speed_mps(speed_mps: float, range_rate_mps: float, params: CoreParams) -> float:
    """The speed (m/s) that must reach zero: relative for moving objects, absolute otherwise."""
    object_speed_mps = speed_mps + range_rate_mps
    if object_speed_mps > params.moving_object_speed_mps:
        return max(0.0, -range_rate_mps)
    return max(0.0, speed_mps)


def is_disjoint(distance_m: float, object_valid: bool, range_m: float, params: CoreParams) -> bool:
    """Stopping Path Disjointness: ``d + standoff_m <= range`` (always true without an object)."""
    return (not object_valid) or distance_m + params.standoff_m <= range_m
