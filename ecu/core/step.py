"""One 10 ms cycle of the ECU core: ``step(state, inputs, params) -> (state, outputs)``.

Order within the cycle:

1. validity: fault flags from timeouts, E2E scores and plausibility
   (:mod:`ecu.core.validity`);
2. speed: reference-speed estimate from the wheels if they are valid, else
   held — or dead-reckoned down at the model deceleration while a held
   contingency brakes (:mod:`ecu.core.speed_estimate`);
   ``adaptive`` only: the achievable-deceleration estimate, from valid wheel
   speeds only (:mod:`ecu.core.decel_estimate`), sets D for this cycle;
3. plan: driver intent, proximity and tightening, the stopping path of the
   (tightened) command and its disjointness (:mod:`ecu.core.strategies`,
   :mod:`ecu.core.stopping_path`);
4. mode: the state machine (:mod:`ecu.core.modes`); a contingency is
   released only when ``plan.released`` (both hold knobs off by default:
   ``contingency_release_ratio`` = 1, ``contingency_release_speed_mps`` = 1000);
5. outputs for the mode, then the output gate (:mod:`ecu.core.output_gate`).

Pure: no I/O, no clock, no logging; the same state and inputs give the same
result.

Written out for speed: the cycle runs 100 times per simulated second and a
Python call costs about 0.1 µs before it does anything, so the helpers below
inline the small functions of the modules named above (each place names the
function it writes out). Those functions stay the documented and tested
definitions: ``tests/ecu/test_step_reference.py`` runs this step beside the
same cycle composed from them and requires identical states and outputs, bit
for bit. Measured on the four paper runs' recorded cycles, against the
composed step, alternating (min of 9, loaded machine): 13.7-17.9 -> 8.3-11.3
µs a step; Python-level calls per step 40 -> 10 (conservative), 47 -> 17
(adaptive, whose estimator is not written out).

Never raises for finite or non-finite float inputs; the shell still guards
against exceptions (internal fault).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from . import decel_estimate
from .degraded import degraded_brake, release_speed_mps
from .output_gate import gated
from .params import NON_DRIVEN_WHEELS, CoreParams
from .relative_stop import moving_margin_m, relative_approach_m
from .speed_estimate import coast_down_speed_mps
from .stopping_path import stopping_distance_m
from .types import REPORT_ONLY_FLAGS, CoreInputs, CoreOutputs, CoreState, FaultFlag, Mode
from .validity import AGE_TOLERANCE_S, fault_flags

_STANDBY, _TIGHTENING, _CONTINGENCY, _FAULT = Mode.STANDBY, Mode.TIGHTENING, Mode.CONTINGENCY, Mode.FAULT
_SLIP, _PEDALS, _CLOCK = 1 << FaultFlag.WHEEL_SLIP, 1 << FaultFlag.PEDALS, 1 << FaultFlag.CLOCK
_SPEED_RADAR, _INTERNAL = 1 << FaultFlag.SPEED_RADAR, 1 << FaultFlag.INTERNAL
_RATE_OR_SEQ = (1 << FaultFlag.RATE) | (1 << FaultFlag.SEQUENCE)
_FULL_THROTTLE_PCT = 100.0  # ecu.core.strategies.FULL_THROTTLE_PCT
_new_tuple = tuple.__new__  # a record built from a tuple, without its generated __new__ (see step)


class Plan(NamedTuple):
    """The planner's result for this cycle, before the mode and the gate."""

    proximity: float
    throttle_limit_pct: float
    decel_request_mps2: float
    tightening_restricts: bool
    stopping_distance_m: float
    disjoint: bool
    #: disjoint with the release margin (``contingency_release_ratio`` >= 1, so released implies
    #: disjoint) and slow enough: a contingency that was active may end.
    released: bool


def _in_path(inputs: CoreInputs, params: CoreParams) -> bool:
    """A valid object in our path: :func:`ecu.core.relevance.in_path` of a valid track."""
    return inputs.object_valid and not abs(inputs.object_lateral_m) > params.vehicle_width_m / 2.0 + params.path_margin_m


def plan_cycle(speed_mps: float, inputs: CoreInputs, params: CoreParams,
               model_decel_mps2: float | None = None) -> Plan:
    """Tighten the driver's command (if the strategy says so) and check its stopping path.

    An object outside our path is no object (:mod:`ecu.core.relevance`); a moving one is
    planned at zero relative speed (:mod:`ecu.core.relative_stop`). ``model_decel_mps2``
    overrides the model deceleration D (``adaptive``: fraction x estimate).
    """
    return Plan(*_plan(speed_mps, inputs, params, model_decel_mps2, _in_path(inputs, params)))


def _plan(speed_mps: float, inputs: CoreInputs, params: CoreParams, model_decel_mps2: float | None,
          valid: bool) -> tuple:
    """:func:`plan_cycle`'s fields as a plain tuple (``valid``: a valid object in our path).

    Written out: ``closing_speed_mps``, ``path_distance_m``, ``proximity`` and ``is_disjoint``
    (:mod:`ecu.core.stopping_path`, :mod:`ecu.core.strategies`). Not moving (or no object), the
    speed that must reach zero is ``max(0, v)`` in both ``closing_speed_mps`` and ``path_distance_m``.
    """
    rate = inputs.object_range_rate_mps
    if valid and speed_mps + rate > params.moving_object_speed_mps:  # ecu.core.relative_stop.is_moving
        return _plan_moving(speed_mps, inputs, params, model_decel_mps2)
    decel = params.model_decel_mps2 if model_decel_mps2 is None else model_decel_mps2
    v, range_m, standoff = max(0.0, speed_mps), inputs.object_range_m, params.standoff_m
    p = 0.0
    if valid:
        nominal_m = stopping_distance_m(v, params.driver_max_accel_mps2, params.hold_time_s, decel)
        p = min(1.0, max(0.0, 1.0 - (range_m - standoff - nominal_m) / params.proximity_margin_m))
    command, throttle, request, restricts = _bounds(p, inputs, params)
    distance = stopping_distance_m(v, command, params.hold_time_s, decel)
    return (p, throttle, request, restricts, distance, (not valid) or distance + standoff <= range_m,
            speed_mps <= params.contingency_release_speed_mps
            and ((not valid) or distance * params.contingency_release_ratio + standoff <= range_m))


def _plan_moving(speed_mps: float, inputs: CoreInputs, params: CoreParams, model_decel_mps2: float | None) -> tuple:
    """:func:`_plan` behind a moving object: relative approach, time-scaled proximity.

    Written out: ``moving_proximity`` and ``relative_disjoint`` (:mod:`ecu.core.relative_stop`).
    """
    rate, range_m, standoff = inputs.object_range_rate_mps, inputs.object_range_m, params.standoff_m
    p = 0.0
    full_throttle_m = relative_approach_m(rate, params.driver_max_accel_mps2, params, model_decel_mps2)
    if not full_throttle_m <= 0.0:  # (NaN: as moving_proximity, which returns 0 only for <= 0)
        margin = range_m - standoff - full_throttle_m
        p = min(1.0, max(0.0, 1.0 - margin / moving_margin_m(max(0.0, -rate), params)))
    command, throttle, request, restricts = _bounds(p, inputs, params)
    approach = relative_approach_m(rate, command, params, model_decel_mps2)
    return (p, throttle, request, restricts, approach, approach <= 0.0 or approach + standoff <= range_m,
            speed_mps <= params.contingency_release_speed_mps
            and (approach * params.contingency_release_ratio <= 0.0
                 or approach * params.contingency_release_ratio + standoff <= range_m))


def _bounds(p: float, inputs: CoreInputs, params: CoreParams) -> tuple[float, float, float, bool]:
    """(command, throttle limit %, deceleration request, restricts) at proximity ``p``.

    Written out: ``tighten`` (or ``NO_TIGHTENING``) and ``driver_accel_mps2`` of
    :mod:`ecu.core.strategies`, the command being ``min(a_drv, a_hi)``.
    """
    a_drv = inputs.accel_pedal * params.driver_max_accel_mps2 - inputs.brake_pedal * params.peak_decel_mps2
    if not params.tightening_enabled:
        return a_drv, _FULL_THROTTLE_PCT, 0.0, False  # min(a_drv, inf) is a_drv for every float, NaN too
    a_max = params.driver_max_accel_mps2
    a_hi = (1.0 - p) * a_max + p * (-params.contingency_decel_mps2)
    throttle = _FULL_THROTTLE_PCT * min(1.0, max(0.0, a_hi / a_max))
    request = max(0.0, -a_hi)
    return min(a_drv, a_hi), throttle, request, throttle < _FULL_THROTTLE_PCT or request > 0.0


def _input_checks(state: CoreState, inputs: CoreInputs, params: CoreParams, mean_mps: float) -> tuple[int, bool, bool]:
    """(fault flags, wheels usable, driver input usable) before the speed estimate.

    Written out: ``braking_now`` and ``input_health`` of :mod:`ecu.core.plausibility` (with
    ``wheel_slip_implausible``, ``pedals_implausible``, ``clock_implausible``) and
    :func:`ecu.core.validity.wheel_speeds_valid`; ``mean_mps`` is the wheels' mean.
    """
    wheels, t = inputs.wheel_speeds_mps, inputs.t_s
    braking = (inputs.brake_pedal > 0.0 or state.prev_decel_request_mps2 > 0.0
               or (state.cycles_since_brake + 1) * params.cycle_s < params.brake_memory_s
               or (state.speed_initialised and mean_mps < state.prev_wheel_mean_mps))
    flags = (fault_flags(inputs, params) | inputs.wheel_rx_flags | inputs.driver_rx_flags | inputs.object_rx_flags
             | inputs.node_flags)
    top = max(wheels)
    slip = not braking and top - min(wheels) > params.wheel_slip_abs_mps + params.wheel_slip_fraction * top
    limit = params.pedal_conflict_fraction
    pedals = inputs.accel_pedal > limit and inputs.brake_pedal > limit
    if slip:
        flags |= _SLIP
    if pedals:
        flags |= _PEDALS
    late = t + AGE_TOLERANCE_S
    if inputs.wheel_rx_t_s > late or inputs.driver_rx_t_s > late or inputs.object_rx_t_s > late:
        flags |= _CLOCK
    wheels_ok = (not (slip or inputs.wheel_rx_flags & _RATE_OR_SEQ)
                 and t - inputs.wheel_rx_t_s <= params.wheel_speeds_timeout_s + AGE_TOLERANCE_S
                 and inputs.wheel_e2e_score < params.e2e_invalid_score
                 and (math.isfinite(sum(wheels)) or all(math.isfinite(v) for v in wheels))
                 and min(wheels) >= 0.0)
    return flags, wheels_ok, not (pedals or inputs.driver_rx_flags & _RATE_OR_SEQ)


def _next_speed(state: CoreState, inputs: CoreInputs, params: CoreParams, wheels_usable: bool,
                mean_mps: float) -> tuple[float, bool, float, int]:
    """(speed estimate, initialised, wheel mean, cycles since braking) after this cycle.

    ``wheels_usable``: the plausibility checks passed and the wheel speeds are valid. Written out:
    ``update_speed_mps`` and ``candidate_speed_mps`` of :mod:`ecu.core.speed_estimate`.
    """
    commanded = inputs.brake_pedal > 0.0 or state.prev_decel_request_mps2 > 0.0
    since_brake = 0 if commanded else min(state.cycles_since_brake + 1, 1_000_000)
    if not wheels_usable:
        speed = state.speed_mps
        if state.held_contingency or state.mode == Mode.CONTINGENCY:
            decel = params.model_decel_mps2  # adaptive: the road's estimate (below the dry value on wet roads)
            if params.adaptive_enabled:
                decel = params.model_decel_fraction * decel_estimate.achievable_decel_mps2(state.decel, params)
            speed = coast_down_speed_mps(speed, decel, params.cycle_s)
        return speed, state.speed_initialised, state.prev_wheel_mean_mps, since_brake
    wheels = inputs.wheel_speeds_mps
    braking = (since_brake * params.cycle_s < params.brake_memory_s
               or (state.speed_initialised and mean_mps < state.prev_wheel_mean_mps))
    # the candidate: the least slipping wheel braking, the slowest non-driven one otherwise
    candidate = max(wheels) if braking else min(map(wheels.__getitem__, NON_DRIVEN_WHEELS[params.driven_axle]))
    if not state.speed_initialised:
        return max(0.0, candidate), True, mean_mps, since_brake
    previous, dt, margin = state.speed_mps, params.cycle_s, params.speed_slope_margin_mps2
    lowest = previous - (params.peak_decel_mps2 + margin) * dt
    highest = previous + (params.driver_max_accel_mps2 + margin) * dt
    return max(0.0, min(highest, max(lowest, candidate))), True, mean_mps, since_brake


def _next_decel(state: CoreState, inputs: CoreInputs, speed_mps: float, params: CoreParams,
                wheels_ok: bool = True) -> tuple[decel_estimate.DecelEstimate, float | None]:
    """``adaptive``: the estimate after this cycle (unchanged without valid wheel speeds: no
    evidence) and the model deceleration ``fraction * a_hat``; other strategies: (state, None).
    ``wheels_ok`` (from :func:`_input_checks`) implies valid wheel speeds."""
    if not params.adaptive_enabled:
        return state.decel, None
    estimate = state.decel
    if state.speed_initialised and wheels_ok:
        request = max(state.prev_decel_request_mps2, inputs.brake_pedal * params.peak_decel_mps2)
        estimate = decel_estimate.update(estimate, state.speed_mps, speed_mps, inputs.wheel_speeds_mps,
                                         request, params)
    return estimate, params.model_decel_fraction * decel_estimate.achievable_decel_mps2(estimate, params)


def _decide(state: CoreState, inputs: CoreInputs, plan: tuple, fault: int, speed_mps: float, wheels_ok: bool,
            params: CoreParams) -> tuple[Mode, int, bool, float, float]:
    """(mode, valid cycles, held contingency, throttle limit %, deceleration request m/s^2) of this cycle.

    Written out: the mode machine (``planned_mode``, ``next_mode`` of :mod:`ecu.core.modes`) and the
    mode's commands. The standstill test (:func:`ecu.core.degraded.release_speed_mps`) only matters
    with a fault and an active contingency, so only then is it worked out (it is pure).
    """
    mode, contingency_mps2 = state.mode, params.contingency_decel_mps2
    if fault:
        held = (state.held_contingency or mode is _CONTINGENCY
                or (mode is _FAULT and state.prev_decel_request_mps2 >= contingency_mps2)) and not (
            release_speed_mps(speed_mps, wheels_ok, inputs, params) <= params.standstill_speed_mps)
        return _FAULT, 0, held, 0.0, contingency_mps2 if held else 0.0
    count = min(params.fault_recovery_cycles, state.valid_cycles + 1)
    _, throttle, request, restricts, _, disjoint, released = plan
    if count < params.fault_recovery_cycles:  # valid data: braking may be requested, throttle stays withheld
        return _FAULT, count, False, 0.0, contingency_mps2 if not disjoint else request
    if not (released if mode is _CONTINGENCY else disjoint):
        return _CONTINGENCY, count, False, 0.0, contingency_mps2
    if restricts:
        return _TIGHTENING, count, False, throttle, request
    return _STANDBY, count, False, _FULL_THROTTLE_PCT, 0.0


def step(state: CoreState, inputs: CoreInputs, params: CoreParams) -> tuple[CoreState, CoreOutputs]:
    """Run one cycle; return the next state and the gated outputs."""
    mean_mps = sum(inputs.wheel_speeds_mps) / 4.0
    flags, wheels_ok, driver_ok = _input_checks(state, inputs, params, mean_mps)
    speed, initialised, wheel_mean, since_brake = _next_speed(state, inputs, params, wheels_ok, mean_mps)
    # _in_path written out: a valid object in our path
    valid = inputs.object_valid and not abs(inputs.object_lateral_m) > params.vehicle_width_m / 2.0 + params.path_margin_m
    if wheels_ok and valid and -inputs.object_range_rate_mps > speed + params.radar_speed_tolerance_mps:
        flags |= _SPEED_RADAR  # ecu.core.plausibility.speed_radar_implausible, written out
        wheels_ok = False
    fault = flags & ~REPORT_ONLY_FLAGS
    estimate, model_decel = _next_decel(state, inputs, speed, params, wheels_ok) if params.adaptive_enabled \
        else (state.decel, None)  # the other strategies: no estimate (_next_decel's answer, without the call)
    plan = _plan(speed, inputs, params, model_decel, valid)
    mode, valid_cycles, held, throttle, decel = _decide(state, inputs, plan, fault, speed, wheels_ok, params)
    if fault and decel < params.contingency_decel_mps2 and degraded_brake(
            speed, wheels_ok, driver_ok, inputs, params):
        decel = params.contingency_decel_mps2  # degraded mode (ecu.core.degraded)
    mode, override, throttle, decel, interventions = gated(mode, throttle, decel)
    if interventions:
        flags |= _INTERNAL
    # built from tuples in the records' field order (ecu.core.types), without the records' generated
    # __new__: 0.45 instead of 0.86 µs for the two (timeit)
    return (_new_tuple(CoreState, (mode, speed, initialised, wheel_mean, decel, since_brake, valid_cycles, held,
                                   state.gate_interventions + interventions, estimate)),
            _new_tuple(CoreOutputs, (mode, override, throttle, decel, flags, plan[0], plan[4], speed, plan[5],
                                     interventions > 0)))
