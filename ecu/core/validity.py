"""Input validity: timeouts from the passed-in time and the codec's E2E score.

An input is invalid while it is timed out or while its E2E validity score is
at or above ``e2e_invalid_score`` (the score comes from ``can_dbc.Receiver``:
+1 per bad or repeated frame, -1 per good fresh frame). Ages are
``t_s - rx_t_s`` with ``rx_t_s`` the time of the latest fresh frame, so no
clock is read here. Timeouts (issue 4): WheelSpeeds and DriverInput 50 ms,
ObjectTrack 250 ms. ``ObjectValid = 0`` is valid data (no object) and is not
a fault. Non-finite or physically impossible values that reach the core are an
internal fault (the codec should have stopped them).

The result is the fault bit field (see :class:`FaultFlag`; ``EcuStatus`` carries each
bit as its own signal, ``ecu.bus_port.FAULT_SIGNALS``) and whether this cycle's wheel
speeds may update the speed estimate: fresh, E2E-valid, finite and not negative.
"""

from __future__ import annotations

import math

from .params import CoreParams
from .types import CoreInputs, FaultFlag

_WHEEL_SPEED_TIMEOUT, _DRIVER_INPUT_TIMEOUT, _OBJECT_TIMEOUT, _E2E, _INTERNAL = (
    1 << FaultFlag[name] for name in ("WHEEL_SPEED_TIMEOUT", "DRIVER_INPUT_TIMEOUT", "OBJECT_TIMEOUT", "E2E", "INTERNAL"))

#: tolerance on age comparisons, so t = k * 0.01 rounding never flips a timeout.
AGE_TOLERANCE_S = 1e-6


def _timed_out(t_s: float, rx_t_s: float, timeout_s: float) -> bool:
    """``not (t - rx_t <= timeout + tolerance)``: an age that is NaN counts as timed out."""
    return not (t_s - rx_t_s <= timeout_s + AGE_TOLERANCE_S)


def input_validity(inputs: CoreInputs, params: CoreParams) -> tuple[int, bool]:
    """(the fault bit field of this cycle's timeouts, E2E scores and impossible values, 0 when every input
    is valid; whether the wheel speeds may update the speed estimate)."""
    t = inputs.t_s
    flags = 0
    wheels_late = _timed_out(t, inputs.wheel_rx_t_s, params.wheel_speeds_timeout_s)
    if wheels_late:
        flags |= _WHEEL_SPEED_TIMEOUT
    if _timed_out(t, inputs.driver_rx_t_s, params.driver_input_timeout_s):
        flags |= _DRIVER_INPUT_TIMEOUT
    if _timed_out(t, inputs.object_rx_t_s, params.object_timeout_s):
        flags |= _OBJECT_TIMEOUT
    limit = params.e2e_invalid_score
    if max(inputs.wheel_e2e_score, inputs.driver_e2e_score, inputs.object_e2e_score) >= limit:
        flags |= _E2E
    # non-finite or impossible values: one sum is finite iff every term is (NaN and inf propagate;
    # our magnitudes cannot overflow), and then the ranges
    wheels = inputs.wheel_speeds_mps
    if (not math.isfinite(sum(wheels) + inputs.accel_pedal + inputs.brake_pedal + inputs.object_range_m
                          + inputs.object_range_rate_mps + t)
            or min(wheels) < 0.0 or inputs.object_range_m < 0.0
            or not (0.0 <= inputs.accel_pedal <= 1.0 and 0.0 <= inputs.brake_pedal <= 1.0)):
        flags |= _INTERNAL
    wheels_valid = (not wheels_late and inputs.wheel_e2e_score < limit
                    # a finite sum proves every term finite; one that overflowed is tested term by term
                    and (math.isfinite(sum(wheels)) or all(math.isfinite(v) for v in wheels))
                    and min(wheels) >= 0.0)
    return flags, wheels_valid
