"""The ECU cycle composed from the documented one-concern functions of ``ecu.core``: the reference.

This is ``ecu/core/step.py`` as it was before its hot path was written out
(issue 10): every check, estimate and plan is a call of the function that
defines and documents it (validity, plausibility, speed_estimate, strategies,
stopping_path, relative_stop, relevance, modes, degraded, output_gate).
``test_step_reference.py`` runs it beside :func:`ecu.core.step` and requires
bit-identical states and outputs, so the written-out step cannot drift from
the definitions their own unit tests pin down.
"""

from __future__ import annotations

from typing import NamedTuple

from ecu.core import decel_estimate
from ecu.core.modes import ModeDecision, next_mode, planned_mode
from ecu.core import output_gate as og
from ecu.core.params import CoreParams
from ecu.core.relative_stop import is_moving, moving_proximity, relative_approach_m, relative_disjoint
from ecu.core.relevance import in_path
from ecu.core.speed_estimate import coast_down_speed_mps, update_speed_mps
from ecu.core.stopping_path import closing_speed_mps, is_disjoint, path_distance_m
from ecu.core.strategies import NO_TIGHTENING, driver_accel_mps2, proximity, tighten
from ecu.core.degraded import degraded_brake, release_speed_mps
from ecu.core.plausibility import braking_now, input_health, speed_radar_implausible
from ecu.core.types import REPORT_ONLY_FLAGS, CoreInputs, CoreOutputs, CoreState, FaultFlag, Mode
from ecu.core.validity import fault_flags, wheel_speeds_valid

_STANDBY, _TIGHTENING, _CONTINGENCY, _FAULT = Mode.STANDBY, Mode.TIGHTENING, Mode.CONTINGENCY, Mode.FAULT


def gate(mode: object, throttle_limit_pct: float, decel_request_mps2: float) -> og.GatedOutputs:
    """The output gate as composed before its fast path: :func:`ecu.core.output_gate._checked` per value."""
    throttle, bad_throttle = og._checked(throttle_limit_pct, og.THROTTLE_RANGE_PCT,
                                         og._THROTTLE_STEPS_PER_PCT, og.SAFE_THROTTLE_PCT)
    decel, bad_decel = og._checked(decel_request_mps2, og.DECEL_RANGE_MPS2, og._DECEL_STEPS_PER_MPS2,
                                   og.SAFE_DECEL_MPS2)
    bad_mode = mode.__class__ is not Mode
    safe_mode = Mode.FAULT if bad_mode else mode
    if bad_throttle or bad_decel or bad_mode:
        safe_mode, throttle = Mode.FAULT, og.SAFE_THROTTLE_PCT
    pass_through = throttle == og.PASS_THROUGH_THROTTLE_PCT and decel == og.PASS_THROUGH_DECEL_MPS2
    return og.GatedOutputs(safe_mode, not pass_through, throttle, decel,
                           int(bad_throttle) + int(bad_decel) + int(bad_mode))


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


def plan_cycle(speed_mps: float, inputs: CoreInputs, params: CoreParams,
               model_decel_mps2: float | None = None) -> Plan:
    """Tighten the driver's command (if the strategy says so) and check its stopping path.

    An object outside our path is no object (:mod:`ecu.core.relevance`); a moving one is
    planned at zero relative speed (:mod:`ecu.core.relative_stop`). ``model_decel_mps2``
    overrides the model deceleration D (``adaptive``: fraction x estimate).
    """
    valid = inputs.object_valid and in_path(inputs.object_lateral_m, params)
    if valid and is_moving(speed_mps, inputs.object_range_rate_mps, params):
        return _plan_moving(speed_mps, inputs, params, model_decel_mps2)
    closing_mps = closing_speed_mps(speed_mps, inputs.object_range_rate_mps, params) if valid else 0.0
    p = proximity(valid, inputs.object_range_m, closing_mps, params, model_decel_mps2)
    tight = tighten(p, params) if params.tightening_enabled else NO_TIGHTENING
    command = min(driver_accel_mps2(inputs.accel_pedal, inputs.brake_pedal, params), tight.accel_upper_mps2)
    distance = path_distance_m(speed_mps, command, valid, inputs.object_range_rate_mps, params, model_decel_mps2)
    return Plan(p, tight.throttle_limit_pct, tight.decel_request_mps2, tight.restricts, distance,
                is_disjoint(distance, valid, inputs.object_range_m, params),
                speed_mps <= params.contingency_release_speed_mps
                and is_disjoint(distance * params.contingency_release_ratio, valid, inputs.object_range_m, params))


def _plan_moving(speed_mps: float, inputs: CoreInputs, params: CoreParams,
                 model_decel_mps2: float | None) -> Plan:
    """:func:`plan_cycle` behind a moving object: relative approach, time-scaled proximity."""
    rate = inputs.object_range_rate_mps
    p = moving_proximity(inputs.object_range_m, rate, params, model_decel_mps2)
    tight = tighten(p, params) if params.tightening_enabled else NO_TIGHTENING
    command = min(driver_accel_mps2(inputs.accel_pedal, inputs.brake_pedal, params), tight.accel_upper_mps2)
    approach = relative_approach_m(rate, command, params, model_decel_mps2)
    disjoint = relative_disjoint(approach, inputs.object_range_m, params)
    return Plan(p, tight.throttle_limit_pct, tight.decel_request_mps2, tight.restricts, approach, disjoint,
                speed_mps <= params.contingency_release_speed_mps
                and relative_disjoint(approach * params.contingency_release_ratio, inputs.object_range_m, params))


def _next_speed(state: CoreState, inputs: CoreInputs, params: CoreParams,
                wheels_usable: bool) -> tuple[float, bool, float, int]:
    """(speed estimate, initialised, wheel mean, cycles since braking) after this cycle.

    ``wheels_usable``: the plausibility checks passed and :func:`wheel_speeds_valid` holds.
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
    mean = sum(wheels) / 4.0
    braking = (
        since_brake * params.cycle_s < params.brake_memory_s
        or (state.speed_initialised and mean < state.prev_wheel_mean_mps)
    )
    speed = update_speed_mps(state.speed_mps, state.speed_initialised, wheels, braking, params)
    return speed, True, mean, since_brake


def _checked_speed(state: CoreState, inputs: CoreInputs, params: CoreParams) -> tuple[int, tuple, bool, bool]:
    """(fault flags, _next_speed's result, wheels usable, driver input usable) after every check."""
    health = input_health(inputs, braking_now(state, inputs, params), params)
    flags = fault_flags(inputs, params) | health.flags
    wheels_ok = health.wheels_ok and wheel_speeds_valid(inputs, params)  # once per cycle: used below and later
    speed_parts = _next_speed(state, inputs, params, wheels_ok)
    if wheels_ok and speed_radar_implausible(speed_parts[0], inputs, params):
        flags |= 1 << FaultFlag.SPEED_RADAR
        wheels_ok = False
    return flags, speed_parts, wheels_ok, health.driver_ok


def _next_decel(state: CoreState, inputs: CoreInputs, speed_mps: float, params: CoreParams,
                wheels_ok: bool = True) -> tuple[decel_estimate.DecelEstimate, float | None]:
    """``adaptive``: the estimate after this cycle (unchanged without valid wheel speeds: no
    evidence) and the model deceleration ``fraction * a_hat``; other strategies: (state, None).
    ``wheels_ok`` (from :func:`_checked_speed`) implies :func:`wheel_speeds_valid`."""
    if not params.adaptive_enabled:
        return state.decel, None
    estimate = state.decel
    if state.speed_initialised and wheels_ok:
        request = max(state.prev_decel_request_mps2, inputs.brake_pedal * params.peak_decel_mps2)
        estimate = decel_estimate.update(estimate, state.speed_mps, speed_mps, inputs.wheel_speeds_mps,
                                         request, params)
    return estimate, params.model_decel_fraction * decel_estimate.achievable_decel_mps2(estimate, params)


def _commands(decision: ModeDecision, plan: Plan, params: CoreParams) -> tuple[float, float]:
    """(throttle limit %, deceleration request m/s^2) for the decided mode."""
    mode = decision.mode
    if mode is _CONTINGENCY:
        return 0.0, params.contingency_decel_mps2
    if mode is _TIGHTENING:
        return plan.throttle_limit_pct, plan.decel_request_mps2
    if mode is _STANDBY:
        return 100.0, 0.0
    if decision.held_contingency:
        return 0.0, params.contingency_decel_mps2
    if decision.recovering:  # valid data: braking may be requested, throttle stays withheld
        decel = params.contingency_decel_mps2 if not plan.disjoint else plan.decel_request_mps2
        return 0.0, decel
    return 0.0, 0.0


def _decide(state: CoreState, inputs: CoreInputs, plan: Plan, fault: int, speed_ok: tuple[float, bool],
            params: CoreParams) -> ModeDecision:
    """The mode machine's decision for this cycle (``speed_ok``: the speed estimate and whether the wheels are valid)."""
    speed, wheels_ok = speed_ok
    contingency_active = state.held_contingency or state.mode is _CONTINGENCY or (
        state.mode is _FAULT and state.prev_decel_request_mps2 >= params.contingency_decel_mps2)
    planned = planned_mode(plan.released if state.mode is _CONTINGENCY else plan.disjoint, plan.tightening_restricts)
    return next_mode(fault, planned, state.valid_cycles, contingency_active,
                     release_speed_mps(speed, wheels_ok, inputs, params) <= params.standstill_speed_mps, params)


def step(state: CoreState, inputs: CoreInputs, params: CoreParams) -> tuple[CoreState, CoreOutputs]:
    """Run one cycle; return the next state and the gated outputs."""
    flags, (speed, initialised, wheel_mean, since_brake), wheels_ok, driver_ok = _checked_speed(
        state, inputs, params)
    fault = flags & ~REPORT_ONLY_FLAGS
    estimate, model_decel = _next_decel(state, inputs, speed, params, wheels_ok) if params.adaptive_enabled \
        else (state.decel, None)  # the other strategies: no estimate (_next_decel's answer, without the call)
    plan = plan_cycle(speed, inputs, params, model_decel)
    decision = _decide(state, inputs, plan, fault, (speed, wheels_ok), params)
    throttle, decel = _commands(decision, plan, params)
    if fault and decel < params.contingency_decel_mps2 and degraded_brake(
            speed, wheels_ok, driver_ok, inputs, params):
        decel = params.contingency_decel_mps2  # degraded mode (ecu.core.degraded)
    gated = gate(decision.mode, throttle, decel)
    if gated.interventions:
        flags |= 1 << FaultFlag.INTERNAL
    # positional, in the records' field order (ecu.core.types): built every cycle, and binding
    # keywords costs about twice as much (0.63 instead of 0.34 µs per record, measured)
    new_state = CoreState(gated.mode, speed, initialised, wheel_mean, gated.brake_decel_request_mps2, since_brake,
                          decision.valid_cycles, decision.held_contingency,
                          state.gate_interventions + gated.interventions, estimate)
    outputs = CoreOutputs(gated.mode, gated.override_active, gated.throttle_limit_pct, gated.brake_decel_request_mps2,
                          flags, plan.proximity, plan.stopping_distance_m, speed, plan.disjoint,
                          gated.interventions > 0)
    return new_state, outputs
