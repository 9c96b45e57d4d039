"""One 10 ms cycle of the ECU core: ``step(state, inputs, params) -> (state, outputs)``.

Order within the cycle, each step a call of the module that defines it:

1. relevance: is the object valid and in our path (:mod:`ecu.core.relevance`);
2. validity: fault flags from timeouts, E2E scores, the receiver's and the
   node's findings and the plausibility checks (:mod:`ecu.core.validity`,
   :mod:`ecu.core.plausibility`);
3. speed: the reference-speed estimate from the wheels if they are usable,
   else held, or dead-reckoned down while a contingency brakes
   (:mod:`ecu.core.speed_estimate`); then the radar cross-check;
4. strategy (:mod:`ecu.core.strategies`): its deceleration estimate, if it
   keeps one, and the model deceleration D of this cycle;
5. plan: proximity, the strategy's bound, the command's stopping path and its
   disjointness (:mod:`ecu.core.plan`);
6. mode: the state machine and the mode's commands (:mod:`ecu.core.modes`);
   while faulted, the degraded check of what is still valid
   (:mod:`ecu.core.degraded`);
7. the output gate (:mod:`ecu.core.output_gate`).

Pure: no I/O, no clock, no logging; the same state and inputs give the same
result. Never raises for finite or non-finite float inputs; the shell still
guards against exceptions (internal fault).
"""

from __future__ import annotations

from .degraded import degraded_brake, release_speed_mps
from .modes import ModeDecision, contingency_active, mode_commands, next_mode, planned_mode
from .output_gate import gate
from .params import CoreParams
from .plan import Plan, plan
from .plausibility import braking_now, input_health, speed_radar_implausible
from .relevance import in_path
from .speed_estimate import SpeedUpdate, next_speed
from .types import REPORT_ONLY_FLAGS, CoreInputs, CoreOutputs, CoreState, FaultFlag, Mode
from .validity import fault_flags, wheel_speeds_valid

_CONTINGENCY = Mode.CONTINGENCY
_SPEED_RADAR, _INTERNAL = 1 << FaultFlag.SPEED_RADAR, 1 << FaultFlag.INTERNAL


def _checked_speed(state: CoreState, inputs: CoreInputs, relevant: bool,
                   params: CoreParams) -> tuple[int, SpeedUpdate, bool, bool]:
    """(fault flags, the speed estimate's update, wheels usable, driver input usable) after every check."""
    health = input_health(inputs, braking_now(state, inputs, params), params)
    flags = fault_flags(inputs, params) | health.flags
    wheels_ok = health.wheels_ok and wheel_speeds_valid(inputs, params)
    speed = next_speed(state, inputs, wheels_ok, params)
    if wheels_ok and speed_radar_implausible(speed.speed_mps, inputs, relevant, params):
        flags |= _SPEED_RADAR
        wheels_ok = False
    return flags, speed, wheels_ok, health.driver_ok


def _decide(state: CoreState, inputs: CoreInputs, cycle_plan: Plan, fault: int, speed: tuple[float, bool],
            params: CoreParams) -> ModeDecision:
    """The mode machine's decision (``speed``: the estimate, and whether the wheels are usable)."""
    speed_mps, wheels_ok = speed
    planned = planned_mode(cycle_plan.released if state.mode is _CONTINGENCY else cycle_plan.disjoint,
                           cycle_plan.tightening_restricts)
    # standstill only matters while faulted (a held contingency ends there)
    stopped = bool(fault) and release_speed_mps(speed_mps, wheels_ok, inputs, params) <= params.standstill_speed_mps
    return next_mode(fault, planned, state.valid_cycles, contingency_active(state, params), stopped, params)


def step(state: CoreState, inputs: CoreInputs, params: CoreParams) -> tuple[CoreState, CoreOutputs]:
    """Run one cycle; return the next state and the gated outputs."""
    relevant = inputs.object_valid and in_path(inputs.object_lateral_m, params)
    flags, speed, wheels_ok, driver_ok = _checked_speed(state, inputs, relevant, params)
    fault = flags & ~REPORT_ONLY_FLAGS
    rules = params.strategy_rules
    estimate = rules.next_estimate(state, inputs, speed.speed_mps, wheels_ok, params)
    cycle_plan = plan(speed.speed_mps, inputs, relevant, rules.model_decel_mps2(estimate, params), params)
    decision = _decide(state, inputs, cycle_plan, fault, (speed.speed_mps, wheels_ok), params)
    throttle, decel = mode_commands(decision, cycle_plan, params)
    if fault and decel < params.contingency_decel_mps2 and degraded_brake(
            speed.speed_mps, wheels_ok, driver_ok, inputs, params):
        decel = params.contingency_decel_mps2  # degraded mode (ecu.core.degraded)
    gated = gate(decision.mode, throttle, decel)
    if gated.interventions:
        flags |= _INTERNAL
    next_state = CoreState(
        mode=gated.mode, speed_mps=speed.speed_mps, speed_initialised=speed.initialised,
        prev_wheel_mean_mps=speed.wheel_mean_mps, prev_decel_request_mps2=gated.brake_decel_request_mps2,
        cycles_since_brake=speed.cycles_since_brake, valid_cycles=decision.valid_cycles,
        held_contingency=decision.held_contingency, gate_interventions=state.gate_interventions + gated.interventions,
        decel=estimate)
    outputs = CoreOutputs(
        mode=gated.mode, override_active=gated.override_active, throttle_limit_pct=gated.throttle_limit_pct,
        brake_decel_request_mps2=gated.brake_decel_request_mps2, fault_flags=flags,
        proximity=cycle_plan.proximity, stopping_distance_m=cycle_plan.stopping_distance_m,
        speed_estimate_mps=speed.speed_mps, disjoint=cycle_plan.disjoint, gate_intervened=gated.interventions > 0)
    return next_state, outputs
