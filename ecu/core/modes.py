"""The mode state machine: STANDBY, TIGHTENING, CONTINGENCY, FAULT.

Rules (issue 4):

* any fault flag -> FAULT, and the count of consecutive valid cycles restarts;
* a contingency that was active when the fault began is *held* while the
  inputs stay invalid, until the car is estimated to have stopped; no new
  braking request is ever started from invalid data;
* after ``fault_recovery_cycles`` consecutive cycles with every input valid
  the ECU leaves FAULT (also at start-up: the start state is FAULT with zero
  valid cycles, so before the first frames the ECU is in FAULT with
  ThrottleLimit 0, and STANDBY follows ``fault_recovery_cycles`` cycles after
  the inputs flow);
* otherwise the planner's verdict is the mode: CONTINGENCY when the stopping
  path is not disjoint, TIGHTENING when tightening restricts, else STANDBY.
  It is re-evaluated every cycle with no hysteresis: that re-evaluation is
  exactly the paper's selective determinism (and its dance).

The mode's commands (:func:`mode_commands`): CONTINGENCY and a held
contingency brake at ``contingency_decel_mps2`` with throttle 0 %;
TIGHTENING passes the strategy's bound; STANDBY passes the driver (100 %,
no request); FAULT withholds throttle and starts no braking, except while
recovering with valid data, when the planner may still brake.

Timers count cycles; no clock is read.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

from .params import CoreParams
from .types import CoreState, Mode

if TYPE_CHECKING:
    from .plan import Plan


class ModeDecision(NamedTuple):
    mode: Mode
    valid_cycles: int
    #: a contingency carried through the fault (only meaningful while faulted).
    held_contingency: bool
    #: the inputs are valid but FAULT is still counting recovery cycles.
    recovering: bool


_STANDBY, _TIGHTENING, _CONTINGENCY, _FAULT = Mode.STANDBY, Mode.TIGHTENING, Mode.CONTINGENCY, Mode.FAULT


def planned_mode(disjoint: bool, tightening_restricts: bool) -> Mode:
    """The planner's verdict for a cycle with valid inputs."""
    if not disjoint:
        return _CONTINGENCY
    return _TIGHTENING if tightening_restricts else _STANDBY


def next_mode(
    flags: int,
    planned: Mode,
    valid_cycles: int,
    contingency_was_active: bool,
    stopped: bool,
    params: CoreParams,
) -> ModeDecision:
    """One transition of the state machine."""
    if flags:
        held = contingency_was_active and not stopped
        return ModeDecision(_FAULT, 0, held, False)
    count = min(params.fault_recovery_cycles, valid_cycles + 1)
    if count < params.fault_recovery_cycles:
        return ModeDecision(_FAULT, count, False, True)
    return ModeDecision(planned, count, False, recovering=False)


def contingency_active(state: CoreState, params: CoreParams) -> bool:
    """A contingency was active last cycle: held, in CONTINGENCY, or FAULT braking at the contingency's
    deceleration (a recovering FAULT that braked for a path that was not disjoint)."""
    return state.held_contingency or state.mode is _CONTINGENCY or (
        state.mode is _FAULT and state.prev_decel_request_mps2 >= params.contingency_decel_mps2)


def mode_commands(decision: ModeDecision, plan: Plan, params: CoreParams) -> tuple[float, float]:
    """(throttle limit %, deceleration request m/s^2) of the decided mode."""
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
        return 0.0, params.contingency_decel_mps2 if not plan.disjoint else plan.decel_request_mps2
    return 0.0, 0.0
