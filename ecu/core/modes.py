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

The mode's commands (:func:`decide` returns them too): CONTINGENCY and a held
contingency brake at ``contingency_decel_mps2`` with throttle 0 %;
TIGHTENING passes the strategy's bound; STANDBY passes the driver (100 %,
no request); FAULT withholds throttle and starts no braking, except while
recovering with valid data, when the planner may still brake.

Timers count cycles; no clock is read.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .params import CoreParams
from .types import CoreState, Mode

if TYPE_CHECKING:
    from .plan import Plan


_STANDBY, _TIGHTENING, _CONTINGENCY, _FAULT = (Mode[name] for name in ("STANDBY", "TIGHTENING", "CONTINGENCY", "FAULT"))


def contingency_active(state: CoreState, params: CoreParams) -> bool:
    """A contingency was active last cycle: held, in CONTINGENCY, or FAULT braking at the contingency's
    deceleration (a recovering FAULT that braked for a path that was not disjoint)."""
    return state.held_contingency or state.mode is _CONTINGENCY or (
        state.mode is _FAULT and state.prev_decel_request_mps2 >= params.contingency_decel_mps2)


def decide(state: CoreState, plan: Plan, fault: int, stopped: bool,
           params: CoreParams) -> tuple[Mode, int, bool, float, float]:
    """One transition and the mode's commands: (mode, valid cycles, held contingency, throttle limit %,
    deceleration request m/s^2).

    ``fault``: the flags that fault this cycle (0: every input valid); ``stopped``: the car is at
    standstill (read only while faulted). A contingency is released when ``plan.released``.
    """
    full = params.contingency_decel_mps2
    if fault:
        held = not stopped and contingency_active(state, params)
        return _FAULT, 0, held, 0.0, full if held else 0.0
    count = min(params.fault_recovery_cycles, state.valid_cycles + 1)
    if count < params.fault_recovery_cycles:  # recovering: braking may be requested, throttle stays withheld
        return _FAULT, count, False, 0.0, plan.decel_request_mps2 if plan.disjoint else full
    if not (plan.released if state.mode is _CONTINGENCY else plan.disjoint):
        return _CONTINGENCY, count, False, 0.0, full
    if plan.tightening_restricts:
        return _TIGHTENING, count, False, plan.throttle_limit_pct, plan.decel_request_mps2
    return _STANDBY, count, False, 100.0, 0.0
