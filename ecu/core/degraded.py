"""Degraded mode: a FAULT that still sees the obstacle it has valid data about (issue 15).

Before, any invalid input meant FAULT: throttle limit 0 and no new braking.
An attacker who invalidated the wheel speeds (a flood, forged values) thus
made the car coast into the obstacle (issue 15, finding 1: 16.5 m/s). Now,
in FAULT, the stopping path is still checked with whatever remains valid,
and the contingency (full braking, held until standstill) is invoked when it
is not disjoint:

* the object must be in our path (:mod:`ecu.core.relevance`) and its track
  usable: not timed out, E2E score below the limit, no rate or sequence
  fault, and not stamped after the cycle time. Without it there is nothing
  to brake for, and no braking is started (as before);
* speed: the wheel-speed estimate if the wheels are usable and agree with
  the radar; otherwise the radar's closing speed ``v_c = max(0, -range_rate)``
  toward the object, stopping to zero *relative* speed (the object keeps its
  speed). For a stationary object this is exactly our own speed, and for an
  object moving away it is the speed that must reach zero to avoid it;
* command held for ``t_h``: the driver's (``a_drv``) if the driver input is
  usable, else a fully pressed accelerator (``driver_max_accel``), the worst
  case the throttle limit of 0 % bounds after the powertrain's lag;
* braking at ``D = min(model_decel, degraded_decel_fraction · peak_decel)``
  (0.8, the conservative strategy's fraction: with a sensor lost the ECU
  keeps the larger margin; with 0.9 the closed-loop test of finding 1 stopped
  only 5 cm short, as the model ignores the actuation and radar lags);
  not disjoint iff ``d + standoff > range`` (:mod:`ecu.core.stopping_path`).

Throttle stays withheld in FAULT (limit 0 %). Mode reported: FAULT with
``BrakeDecelRequest`` = the contingency's deceleration. An attack on one
input thus never blinds the ECU to an obstacle it still sees through valid
data, and braking is only ever started from valid radar data.
"""

from __future__ import annotations

from .intent import driver_accel_mps2
from .params import CoreParams
from .relevance import in_path
from .stopping_path import closing_speed_mps, stopping_distance_m
from .types import RECEIVER_FLAGS, CoreInputs
from .validity import AGE_TOLERANCE_S


def object_usable(inputs: CoreInputs, params: CoreParams) -> bool:
    """The object track is fresh (age 0 .. timeout), E2E-valid, and in rate and sequence."""
    return (
        -AGE_TOLERANCE_S <= inputs.t_s - inputs.object_rx_t_s <= params.object_timeout_s + AGE_TOLERANCE_S
        and inputs.object_e2e_score < params.e2e_invalid_score
        and not inputs.object_rx_flags & RECEIVER_FLAGS
    )


def relevant_track(inputs: CoreInputs, params: CoreParams) -> bool:
    """A valid object in our path (:mod:`ecu.core.relevance`) from a usable track."""
    return inputs.object_valid and in_path(inputs.object_lateral_m, params) and object_usable(inputs, params)


def radar_closing_speed_mps(inputs: CoreInputs) -> float:
    """The radar's closing speed toward the object (m/s), 0 when it moves away."""
    return max(0.0, -inputs.object_range_rate_mps)


def release_speed_mps(speed_mps: float, wheels_ok: bool, inputs: CoreInputs, params: CoreParams) -> float:
    """The speed a held contingency waits to fall to standstill: without usable wheels, never below the
    closing speed of a usable track."""
    if wheels_ok or not relevant_track(inputs, params):
        return speed_mps
    return max(speed_mps, radar_closing_speed_mps(inputs))


def degraded_brake(speed_mps: float, wheels_ok: bool, driver_ok: bool, inputs: CoreInputs,
                   params: CoreParams) -> bool:
    """Whether the degraded check invokes the contingency this cycle (see the module doc)."""
    if not relevant_track(inputs, params):
        return False
    if wheels_ok:
        v = closing_speed_mps(speed_mps, inputs.object_range_rate_mps, params)
    else:
        v = radar_closing_speed_mps(inputs)
    a = driver_accel_mps2(inputs.accel_pedal, inputs.brake_pedal, params) if driver_ok \
        else params.driver_max_accel_mps2
    decel = min(params.model_decel_mps2, params.degraded_decel_fraction * params.peak_decel_mps2)
    d = stopping_distance_m(v, a, params.hold_time_s, decel)
    return d + params.standoff_m > inputs.object_range_m
