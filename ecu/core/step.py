"""One 10 ms cycle of the ECU core: ``step(state, inputs, params) -> (state, outputs)``.

Order within the cycle, each step a call of the module that defines it:

1. track confirmation and relevance: has the radar reported the object
   consistently (:mod:`ecu.core.track_confirmation`), is it valid and in our
   predicted path (:mod:`ecu.core.relevance`, at the last cycle's speed:
   the speed checks below need the relevance); an unconfirmed object is no object to
   every later step, so it never starts braking;
2. validity: fault flags from timeouts, E2E scores and impossible values
   (:mod:`ecu.core.validity`), the receiver's and the node's findings and the
   plausibility checks (:mod:`ecu.core.plausibility`);
3. speed: the reference-speed estimate from the wheels if they are usable,
   else held, or dead-reckoned down while a contingency brakes
   (:mod:`ecu.core.speed_estimate`); then the radar cross-check;
4. strategy (:mod:`ecu.core.strategies`): its deceleration estimate, if it
   keeps one, and the model deceleration D of this cycle;
5. plan: proximity, the strategy's bound, the command's stopping path and its
   disjointness (:mod:`ecu.core.plan`); with planar tracks, the stopping region
   over every track and what it adds to the plan's disjointness (:mod:`ecu.core.planar`);
6. mode: the state machine and the mode's commands (:func:`ecu.core.modes.decide`);
   while faulted, the degraded check of what is still valid
   (:mod:`ecu.core.degraded`); with steering authority, the steering contingency's
   request and the braking the friction circle leaves beside it (:mod:`ecu.core.steering`);
7. the output gate (:mod:`ecu.core.output_gate`).

Pure: no I/O, no clock, no logging; the same state and inputs give the same
result. Never raises for finite or non-finite float inputs; the shell still
guards against exceptions (internal fault).
"""

from __future__ import annotations

from .degraded import degraded_brake, release_speed_mps
from .modes import decide
from .output_gate import gate, gate_steering
from .params import CoreParams
from .plan import plan
from .planar import merged, region_cycle, report
from .region.narrowing import Turn
from .plausibility import Health, input_health, speed_radar_implausible
from .relevance import object_in_path
from .speed_estimate import next_speed
from .steering import REQUEST_RANGE_RAD, shortfall, steering, steering_held
from .track_confirmation import confirmed, next_track
from .types import REPORT_ONLY_FLAGS, CoreInputs, CoreOutputs, CoreState, FaultFlag
from .validity import input_validity
from .way_out import next_way_out, turn

_SPEED_RADAR, _INTERNAL = (1 << FaultFlag[name] for name in ("SPEED_RADAR", "INTERNAL"))


def _checked_speed(state: CoreState, inputs: CoreInputs, relevant: bool,
                   params: CoreParams) -> tuple[int, bool, Health, tuple[float, bool, float, int]]:
    """(the flags and whether the wheels may be used, after every check; the input health of
    :func:`input_health`; the speed fields of the next state); ``relevant``: the object is valid and in our
    path. The checks' outcome beside the health, not a copy of it (``Health._replace`` cost 3 µs a cycle)."""
    flags, wheels_valid = input_validity(inputs, params)
    health = input_health(state, inputs, params)
    flags |= health.flags
    wheels_ok = health.wheels_ok and wheels_valid
    speed = next_speed(state, inputs, wheels_ok, params)
    if wheels_ok and speed_radar_implausible(speed[0], inputs, relevant, params):
        flags |= _SPEED_RADAR
        wheels_ok = False
    return flags, wheels_ok, health, speed


def step(state: CoreState, inputs: CoreInputs, params: CoreParams) -> tuple[CoreState, CoreOutputs]:
    """Run one cycle; return the next state and the gated outputs."""
    track = next_track(state.track, inputs, params)
    confirmed_track = confirmed(track, params)
    in_our_path = inputs.object_valid and object_in_path(inputs, state.speed_mps, params)  # last cycle's speed
    relevant = confirmed_track and in_our_path
    flags, wheels_ok, health, (speed, initialised, free_mean, since_brake) = _checked_speed(
        state, inputs, relevant, params)
    driver_ok = health.driver_ok
    fault = flags & ~REPORT_ONLY_FLAGS
    estimate, decel_mps2 = params.strategy_rules.cycle_decel(state, inputs, speed, wheels_ok, params)
    cycle_plan = plan(speed, inputs, relevant, decel_mps2, params)
    way = turn(state, params)
    region = region_cycle(speed, inputs, cycle_plan, decel_mps2, params, in_our_path, way) \
        if inputs.tracks else None
    cycle_plan = merged(cycle_plan, region, steering_held(state, speed, params), params)
    # standstill only matters while faulted (a held contingency ends there)
    stopped = bool(fault) and release_speed_mps(speed, wheels_ok, inputs, params) <= params.standstill_speed_mps
    mode, valid_cycles, held, throttle, decel = decide(state, cycle_plan, fault, stopped, params)
    if (fault and decel < params.contingency_decel_mps2 and confirmed_track
            and degraded_brake(speed, wheels_ok, driver_ok, inputs, params)):
        decel = params.contingency_decel_mps2  # degraded mode (ecu.core.degraded)
    steer = steering(state, mode, region, shortfall(relevant, cycle_plan, inputs.object_range_m),
                     inputs.steering_wheel_rad, inputs.yaw_rate_radps, speed, decel_mps2, params)
    gated = gate(mode, throttle, min(decel, steer.decel_mps2))
    steer_active, steer_rad, steer_bad = gate_steering(steer.active, steer.request_rad, REQUEST_RANGE_RAD)
    interventions = gated.interventions + steer_bad
    slow_cycles, backoffs = next_way_out(state, speed, region, way == Turn.TAKING, params)
    if interventions:
        flags |= _INTERNAL
    next_state = CoreState(
        mode=gated.mode, speed_mps=speed, speed_initialised=initialised, prev_free_wheel_mean_mps=free_mean,
        prev_decel_request_mps2=gated.brake_decel_request_mps2, cycles_since_brake=since_brake,
        valid_cycles=valid_cycles, held_contingency=held,
        gate_interventions=state.gate_interventions + interventions, decel=estimate, track=track,
        cycles_since_drive=health.cycles_since_drive, traction_excess_mps=health.traction_excess_mps,
        steer_curvature_1pm=steer.curvature_1pm, steer_request_rad=steer_rad, steer_evasion=steer.evasion,
        slow_cycles=slow_cycles, way_out_backoffs=backoffs)
    outputs = CoreOutputs(
        mode=gated.mode, override_active=gated.override_active, throttle_limit_pct=gated.throttle_limit_pct,
        brake_decel_request_mps2=gated.brake_decel_request_mps2, fault_flags=flags,
        proximity=cycle_plan.proximity, stopping_distance_m=cycle_plan.stopping_distance_m,
        speed_estimate_mps=speed, disjoint=cycle_plan.disjoint, gate_intervened=interventions > 0,
        steer_active=steer_active, steer_request_rad=steer_rad, region=report(region))
    return next_state, outputs
