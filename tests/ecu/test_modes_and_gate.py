"""The mode state machine and the output gate."""

import math

import numpy as np

import pytest

from can_dbc import LAYOUTS
from ecu.core import CoreParams, Mode
from ecu.core import output_gate as og
from ecu.core.modes import next_mode, planned_mode

P = CoreParams()


def test_planner_verdicts():
    assert planned_mode(False, True) == Mode.CONTINGENCY
    assert planned_mode(True, True) == Mode.TIGHTENING
    assert planned_mode(True, False) == Mode.STANDBY


def test_fault_recovery_counts_valid_cycles():
    count = 0
    for k in range(P.fault_recovery_cycles):
        d = next_mode(0, Mode.STANDBY, count, False, False, P)
        count = d.valid_cycles
        expected = Mode.STANDBY if k == P.fault_recovery_cycles - 1 else Mode.FAULT
        assert d.mode == expected and d.recovering == (expected == Mode.FAULT)
    again = next_mode(0b1, Mode.STANDBY, count, False, False, P)
    assert again.mode == Mode.FAULT and again.valid_cycles == 0


def test_contingency_is_held_through_a_fault_until_stopped():
    assert next_mode(0b100, Mode.STANDBY, 10, True, False, P).held_contingency
    assert not next_mode(0b100, Mode.STANDBY, 10, True, True, P).held_contingency
    assert not next_mode(0b100, Mode.CONTINGENCY, 10, False, False, P).held_contingency


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
