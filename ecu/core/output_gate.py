"""The output gate: the last guard between the planner and the bus. Deny by default.

Every output is checked on its own: a value that is not finite or lies
outside its DBC range is replaced by its safe value and the intervention is
counted. Safe values deny: ``ThrottleLimit = 0 %`` (no throttle authority),
``BrakeDecelRequest = 0`` (no unrequested braking; the driver's own brake
stays effective), ``Mode = FAULT``; after any replacement the throttle limit
is also set to its safe value. Values are quantised to the DBC
resolution so the pass-through test below is exact.

``OverrideActive`` is 0 only when the outputs equal the pass-through values
``ThrottleLimit = 100 %`` and ``BrakeDecelRequest = 0``; any doubt means 1.
The limits and resolutions are ``SafetyOverride``'s in
``can_dbc/active_safety.dbc`` (read through :mod:`can_dbc.contract`).

Any real number passes the type check (``float``, ``int``, and NumPy's
scalars such as ``np.float64``, which the plant wrapper or a strategy may
hand over); ``bool``, ``None``, strings and other objects are replaced.
"""

from __future__ import annotations

import math
import numbers
from typing import NamedTuple, cast

from can_dbc.contract import signal_range, signal_resolution

from .types import Mode

THROTTLE_RANGE_PCT = signal_range("SafetyOverride", "ThrottleLimit")
THROTTLE_RESOLUTION_PCT = signal_resolution("SafetyOverride", "ThrottleLimit")
DECEL_RANGE_MPS2 = signal_range("SafetyOverride", "BrakeDecelRequest")
DECEL_RESOLUTION_MPS2 = signal_resolution("SafetyOverride", "BrakeDecelRequest")
SAFE_THROTTLE_PCT = 0.0
SAFE_DECEL_MPS2 = 0.0
PASS_THROUGH_THROTTLE_PCT = 100.0
PASS_THROUGH_DECEL_MPS2 = 0.0
_THROTTLE_STEPS_PER_PCT = float(round(1.0 / THROTTLE_RESOLUTION_PCT))
_DECEL_STEPS_PER_MPS2 = float(round(1.0 / DECEL_RESOLUTION_MPS2))
_FAULT = Mode["FAULT"]


class GatedOutputs(NamedTuple):
    mode: Mode
    override_active: bool
    throttle_limit_pct: float
    brake_decel_request_mps2: float
    interventions: int


def _checked(value: object, limits: tuple[float, float], steps_per_unit: float, safe: float) -> tuple[float, bool]:
    """(the value quantised to the DBC resolution, False), or (``safe``, True) if it is not a finite real
    number inside ``limits`` once quantised."""
    cls = value.__class__
    if cls is float or cls is int:  # the common case costs two identity tests
        number = cast(float, value)
    elif isinstance(value, numbers.Real) and not isinstance(value, bool):
        number = float(value)  # e.g. np.float64, np.int32
    else:
        return safe, True
    if not math.isfinite(number):
        return safe, True
    # dividing by a power of ten gives the float nearest to the decimal, so equality tests are exact
    quantised = round(number * steps_per_unit) / steps_per_unit
    if not limits[0] <= quantised <= limits[1]:
        return safe, True
    return quantised, False


def gate(mode: object, throttle_limit_pct: object, decel_request_mps2: object) -> GatedOutputs:
    """Check and quantise one cycle's outputs; count every replaced value."""
    throttle, bad_throttle = _checked(throttle_limit_pct, THROTTLE_RANGE_PCT,
                                      _THROTTLE_STEPS_PER_PCT, SAFE_THROTTLE_PCT)
    decel, bad_decel = _checked(decel_request_mps2, DECEL_RANGE_MPS2,
                                _DECEL_STEPS_PER_MPS2, SAFE_DECEL_MPS2)
    bad_mode = mode.__class__ is not Mode
    safe_mode = _FAULT if bad_mode else cast(Mode, mode)
    if bad_throttle or bad_decel or bad_mode:
        # Any doubt about this cycle's decision withdraws throttle authority altogether.
        safe_mode = _FAULT
        throttle = SAFE_THROTTLE_PCT
    pass_through = throttle == PASS_THROUGH_THROTTLE_PCT and decel == PASS_THROUGH_DECEL_MPS2
    return GatedOutputs(safe_mode, not pass_through, throttle, decel, bad_throttle + bad_decel + bad_mode)


def gate_steering(active: bool, request_rad: float, limits_rad: tuple[float, float]) -> tuple[bool, float, int]:
    """``SteeringOverride``'s (SteerActive, SteerAngleRequest rad, interventions): a request that is not a finite
    real number inside ``limits_rad`` is replaced by the pass-through (inactive, 0) and counted; an inactive
    request is always 0."""
    if not active:
        return False, 0.0, 0
    cls = request_rad.__class__
    if (cls is not float and cls is not int and (not isinstance(request_rad, numbers.Real)
                                                 or isinstance(request_rad, bool))):
        return False, 0.0, 1
    if not (math.isfinite(request_rad) and limits_rad[0] <= request_rad <= limits_rad[1]):
        return False, 0.0, 1
    return True, float(request_rad), 0
