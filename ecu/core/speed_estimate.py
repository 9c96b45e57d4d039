"""Reference-speed estimate from four wheel speeds, robust to braking and traction slip.

Method (the classic ABS "reference speed", e.g. Bosch *Automotive Handbook*,
ABS chapter): wheel slip only ever makes a wheel *slower* than the car while
braking and *faster* than the car while driving. So each cycle a candidate is
picked from the wheels:

* braking (brake pedal pressed, our previous cycle requested deceleration, or
  the mean wheel speed is falling): ``candidate = max(wheels)``, the least
  slipping wheel;
* otherwise (accelerating or cruising): ``candidate = min(non-driven wheels)``;
  non-driven wheels carry no traction torque (``driven_axle`` param; the plant
  is front-wheel driven, so the rear axle; ``"all"`` uses all four).

The estimate then follows the candidate through a slope limiter, because the
car cannot change speed faster than physics allows even when every wheel
locks or spins::

    v[k] = clamp(candidate, v[k-1] - (peak_decel + margin) * dt,
                            v[k-1] + (driver_max_accel + margin) * dt)

and is never negative. The first valid sample initialises the estimate
directly. While the wheel speeds are not usable the estimate is held, or,
while a contingency brakes, dead-reckoned down at the strategy's model
deceleration (:func:`coast_down_speed_mps`). Pure functions; the state is the
speed fields of :class:`ecu.core.types.CoreState`.
"""

from __future__ import annotations

from .params import NON_DRIVEN_WHEELS, CoreParams
from .types import CoreInputs, CoreState, Mode

#: cycles since braking saturate here
_CYCLES_MAX = 1_000_000


def update_speed_mps(
    previous_mps: float,
    initialised: bool,
    wheels_mps: tuple[float, ...],
    braking: bool,
    params: CoreParams,
) -> float:
    """Next speed estimate (m/s) from the previous estimate and this cycle's wheel speeds.

    The candidate: braking, the fastest wheel (the least slipping); otherwise the slowest non-driven one.
    """
    candidate = max(wheels_mps) if braking else min(map(wheels_mps.__getitem__, NON_DRIVEN_WHEELS[params.driven_axle]))
    if not initialised:
        return max(0.0, candidate)
    dt = params.cycle_s
    margin = params.speed_slope_margin_mps2
    lowest = previous_mps - (params.peak_decel_mps2 + margin) * dt
    highest = previous_mps + (params.driver_max_accel_mps2 + margin) * dt
    return max(0.0, min(highest, max(lowest, candidate)))


def coast_down_speed_mps(previous_mps: float, decel_mps2: float, dt_s: float) -> float:
    """Dead-reckoned speed while wheel speeds are invalid and we are braking at ``decel_mps2``.

    Used only to decide when a held contingency may end; the caller passes the
    model deceleration (below peak), so the estimate stays above the true
    speed and the hold lasts at least as long as the real stop.
    """
    return max(0.0, previous_mps - decel_mps2 * dt_s)


def next_speed(state: CoreState, inputs: CoreInputs, wheels_usable: bool,
               params: CoreParams) -> tuple[float, bool, float, int]:
    """The speed fields of the next state: (speed estimate m/s, initialised, mean wheel speed m/s, cycles
    since braking was commanded, saturating). ``wheels_usable``: the wheel speeds are valid and plausible.

    Braking, for the candidate: commanded within ``brake_memory_s`` (brake pressure outlives the
    command), or the mean wheel speed falling.
    """
    commanded = inputs.brake_pedal > 0.0 or state.prev_decel_request_mps2 > 0.0
    since_brake = 0 if commanded else min(state.cycles_since_brake + 1, _CYCLES_MAX)
    if not wheels_usable:
        speed = state.speed_mps
        if state.held_contingency or state.mode == Mode.CONTINGENCY:
            decel = params.strategy_rules.model_decel_mps2(state.decel, params)
            speed = coast_down_speed_mps(speed, decel, params.cycle_s)
        return speed, state.speed_initialised, state.prev_wheel_mean_mps, since_brake
    wheels = inputs.wheel_speeds_mps
    mean = sum(wheels) / 4.0
    braking = (since_brake * params.cycle_s < params.brake_memory_s
               or (state.speed_initialised and mean < state.prev_wheel_mean_mps))
    speed = update_speed_mps(state.speed_mps, state.speed_initialised, wheels, braking, params)
    return speed, True, mean, since_brake
