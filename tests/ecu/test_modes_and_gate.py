"""The mode state machine and the output gate."""

import math

import numpy as np

import pytest

from can_dbc import LAYOUTS
from ecu.core import CoreParams, CoreState, Mode, Plan
from ecu.core import output_gate as og
from ecu.core.modes import decide

P = CoreParams()


def _plan(disjoint: bool = True, restricts: bool = False, released: bool | None = None) -> Plan:
    return Plan(proximity=0.5, throttle_limit_pct=40.0 if restricts else 100.0,
                decel_request_mps2=2.0 if restricts else 0.0, tightening_restricts=restricts,
                stopping_distance_m=30.0, disjoint=disjoint, released=disjoint if released is None else released)


def _settled(mode: Mode = Mode.STANDBY, **fields) -> CoreState:
    return CoreState(mode=mode, valid_cycles=P.fault_recovery_cycles, **fields)


def test_planner_verdicts_and_their_commands():
    assert decide(_settled(), _plan(disjoint=False), 0, False, P) == (Mode.CONTINGENCY, 10, False, 0.0, 15.0)
    assert decide(_settled(), _plan(restricts=True), 0, False, P) == (Mode.TIGHTENING, 10, False, 40.0, 2.0)
    assert decide(_settled(), _plan(), 0, False, P) == (Mode.STANDBY, 10, False, 100.0, 0.0)


def test_a_contingency_is_released_only_with_the_release_margin():
    assert decide(_settled(Mode.CONTINGENCY), _plan(released=False), 0, False, P)[0] == Mode.CONTINGENCY
    assert decide(_settled(Mode.CONTINGENCY), _plan(released=True), 0, False, P)[0] == Mode.STANDBY
    assert decide(_settled(Mode.STANDBY), _plan(released=False), 0, False, P)[0] == Mode.STANDBY


def test_fault_recovery_counts_valid_cycles():
    state = CoreState()
    for k in range(P.fault_recovery_cycles):
        mode, count, held, throttle, decel = decide(state, _plan(), 0, False, P)
        expected = Mode.STANDBY if k == P.fault_recovery_cycles - 1 else Mode.FAULT
        assert (mode, count) == (expected, k + 1) and not held
        assert throttle == (100.0 if expected == Mode.STANDBY else 0.0)
        state = state._replace(mode=mode, valid_cycles=count)
    # recovering with valid data: braking may be requested (a path that is not disjoint: full braking)
    assert decide(CoreState(), _plan(disjoint=False), 0, False, P)[3:] == (0.0, 15.0)
    assert decide(CoreState(), _plan(restricts=True), 0, False, P)[3:] == (0.0, 2.0)
    again = decide(state, _plan(), 0b1, False, P)
    assert again[:2] == (Mode.FAULT, 0) and again[3:] == (0.0, 0.0)


def test_contingency_is_held_through_a_fault_until_stopped():
    braking = CoreState(mode=Mode.CONTINGENCY, prev_decel_request_mps2=15.0, valid_cycles=10)
    assert decide(braking, _plan(), 0b100, False, P)[2:] == (True, 0.0, 15.0)
    assert decide(braking, _plan(), 0b100, True, P)[2:] == (False, 0.0, 0.0)
    held = CoreState(mode=Mode.FAULT, held_contingency=True)
    assert decide(held, _plan(), 0b100, False, P)[2] is True
    assert decide(_settled(), _plan(disjoint=False), 0b100, False, P)[2:] == (False, 0.0, 0.0)  # never started


def test_gate_limits_match_the_dbc():
    sigs = {s.name: s for s in LAYOUTS["SafetyOverride"].signals}
    assert og.THROTTLE_RANGE_PCT == (sigs["ThrottleLimit"].minimum, sigs["ThrottleLimit"].maximum)
    assert og.DECEL_RANGE_MPS2 == (sigs["BrakeDecelRequest"].minimum, sigs["BrakeDecelRequest"].maximum)
    assert og.THROTTLE_RESOLUTION_PCT == sigs["ThrottleLimit"].scale
    assert og.DECEL_RESOLUTION_MPS2 == sigs["BrakeDecelRequest"].scale


def test_gate_pass_through_only_for_pass_through_values():
    g = og.gate(Mode.STANDBY, 100.0, 0.0)
    assert (g.override_active, g.interventions) == (False, 0)
    assert og.gate(Mode.TIGHTENING, 99.9, 0.0).override_active
    assert og.gate(Mode.TIGHTENING, 100.0, 0.01).override_active


@pytest.mark.parametrize("throttle,decel", [(math.nan, 0.0), (100.0, math.inf), (120.0, 0.0), (50.0, -1.0), (0.0, 16.0)])
def test_gate_denies_bad_values_and_counts_them(throttle, decel):
    g = og.gate(Mode.STANDBY, throttle, decel)
    assert g.interventions >= 1
    assert g.mode == Mode.FAULT and g.throttle_limit_pct == 0.0 and g.override_active
    assert 0.0 <= g.brake_decel_request_mps2 <= 15.0


def test_gate_rejects_an_unknown_mode():
    g = og.gate(7, 100.0, 0.0)
    assert g.mode == Mode.FAULT and g.interventions == 1 and g.override_active


@pytest.mark.parametrize("scalar", [np.float64, np.float32, np.int64])
def test_gate_passes_numpy_scalars_like_floats(scalar):
    # issue 10: gate() sent FAULT for an np.float64 (its class is not float or int)
    assert og.gate(Mode.STANDBY, scalar(100.0), scalar(0.0)) == og.gate(Mode.STANDBY, 100.0, 0.0)
    gated = og.gate(Mode.TIGHTENING, scalar(40.0), scalar(2.0))
    assert gated.mode == Mode.TIGHTENING and gated.interventions == 0
    assert gated.throttle_limit_pct == 40.0 and type(gated.throttle_limit_pct) is float


@pytest.mark.parametrize("bad", [True, "100", None, [100.0], complex(1, 0)])
def test_gate_still_refuses_what_is_not_a_real_number(bad):
    gated = og.gate(Mode.STANDBY, bad, 0.0)
    assert gated.mode == Mode.FAULT and gated.interventions == 1 and gated.throttle_limit_pct == 0.0
