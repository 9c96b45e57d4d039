"""Reference-speed estimate from four wheel speeds, robust to braking and traction slip.

Method (the classic ABS "reference speed", e.g. Bosch *Automotive Handbook*,
ABS chapter): wheel slip only ever makes a wheel *slower* than the car while
braking and *faster* than the car while driving. So each cycle a candidate is
picked from the wheels:

* braking (brake pedal pressed, our previous cycle requested deceleration, or
  the mean speed of the non-driven wheels is falling): ``candidate =
  max(wheels)``, the least slipping wheel;
* otherwise (accelerating or cruising): ``candidate = min(non-driven wheels)``;
  non-driven wheels carry no traction torque (``driven_axle`` param; the plant
  is front-wheel driven, so the rear axle; ``"all"`` uses all four).

Only the non-driven wheels tell whether the car slows: driven wheels that spin
down after wheelspin fall while the car still accelerates, and were taken for
braking (issue 25: the estimate then followed a spinning wheel, 19 m/s above
the car at the end of a full-throttle run on friction 0.3). Estimating the
vehicle speed from the non-driven wheels while drive torque acts is how ABS/TCS
controllers do it (van Zanten, Erhardt, Pfaff, "VDC, the Vehicle Dynamics
Control System of Bosch", SAE 950759, 1995, and the Bosch *Automotive
Handbook*, TCS chapter: the reference speed of a driven axle's wheel slip
comes from the non-driven wheels; both cited from memory, unconfirmed here).

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
from .types import CYCLES_MAX, CoreInputs, CoreState, Mode

_CONTINGENCY = Mode["CONTINGENCY"]


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


def free_wheel_mean_mps(wheels_mps: tuple[float, ...], params: CoreParams) -> float:
    """Mean speed of the non-driven wheels (all four for all-wheel drive)."""
    free = NON_DRIVEN_WHEELS[params.driven_axle]
    return sum(map(wheels_mps.__getitem__, free)) / len(free)


def brake_commanded(state: CoreState, inputs: CoreInputs) -> bool:
    """The driver's brake pedal is pressed, or we requested deceleration last cycle."""
    return inputs.brake_pedal > 0.0 or state.prev_decel_request_mps2 > 0.0


def wheels_braked(state: CoreState, inputs: CoreInputs, params: CoreParams) -> bool:
    """Braking as the reference speed sees it: commanded within ``brake_memory_s`` (brake pressure
    outlives the command), or the non-driven wheels slowing."""
    if brake_commanded(state, inputs) or (state.cycles_since_brake + 1) * params.cycle_s < params.brake_memory_s:
        return True
    free_mean_mps = free_wheel_mean_mps(inputs.wheel_speeds_mps, params)
    return state.speed_initialised and free_mean_mps < state.prev_free_wheel_mean_mps


def next_speed(state: CoreState, inputs: CoreInputs, wheels_usable: bool,
               params: CoreParams) -> tuple[float, bool, float, int]:
    """The speed fields of the next state: (speed estimate m/s, initialised, mean speed of the non-driven
    wheels m/s, cycles since braking was commanded, saturating). ``wheels_usable``: the wheel speeds are
    valid and plausible. Braking, for the candidate: :func:`wheels_braked`.
    """
    since_brake = 0 if brake_commanded(state, inputs) else min(state.cycles_since_brake + 1, CYCLES_MAX)
    if not wheels_usable:
        speed = state.speed_mps
        if state.held_contingency or state.mode == _CONTINGENCY:
            decel = params.strategy_rules.model_decel_mps2(state.decel, params)
            speed = coast_down_speed_mps(speed, decel, params.cycle_s)
        return speed, state.speed_initialised, state.prev_free_wheel_mean_mps, since_brake
    wheels = inputs.wheel_speeds_mps
    braking = wheels_braked(state, inputs, params)
    speed = update_speed_mps(state.speed_mps, state.speed_initialised, wheels, braking, params)
    return speed, True, free_wheel_mean_mps(wheels, params), since_brake
