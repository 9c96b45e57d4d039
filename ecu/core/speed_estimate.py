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
directly. Pure function; no state beyond what is passed in.
"""

from __future__ import annotations

from .params import NON_DRIVEN_WHEELS, CoreParams


def candidate_speed_mps(wheels_mps: tuple[float, ...], braking: bool, params: CoreParams) -> float:
    """The wheel speed the estimate moves toward this cycle (m/s)."""
    if braking:
        return max(wheels_mps)
    return min(wheels_mps[i] for i in NON_DRIVEN_WHEELS[params.driven_axle])


def update_speed_mps(
    previous_mps: float,
    initialised: bool,
    wheels_mps: tuple[float, ...],
    braking: bool,
    params: CoreParams,
) -> float:
    """Next speed estimate (m/s) from the previous estimate and this cycle's wheel speeds."""
    candidate = candidate_speed_mps(wheels_mps, braking, params)
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
