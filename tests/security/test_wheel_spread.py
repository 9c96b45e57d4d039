"""Wheelspin is driving, forged wheel speeds are not (issue 25, item 3; ecu.core.plausibility).

The plant is front-wheel driven: wheels FL, FR are driven, RL, RR roll free. A drive here is a
sequence of cycles, each a wheel-speed tuple with the accelerator at ``accel``; the car's speed
(the non-driven wheels) is 20 m/s unless a test says otherwise.
"""

import pytest

from ecu.core import CoreInputs, CoreParams, CoreState, FaultFlag, Mode, step

P = CoreParams(strategy="none")
SLIP = 1 << FaultFlag.WHEEL_SLIP
CAR_MPS = 20.0


def _inputs(k, wheels, accel):
    t = k * P.cycle_s
    return CoreInputs(t_s=t, wheel_speeds_mps=wheels, accel_pedal=accel, wheel_rx_t_s=t, driver_rx_t_s=t,
                      object_rx_t_s=t)


def _drive(cycles, accel, state=None, start=0):
    """Run ``cycles`` (wheel tuples) from ``state`` (default: 100 cycles of straight driving at the
    same accelerator, so the ECU is in STANDBY and the accelerator's memory is what ``accel`` says);
    return the last state and each cycle's outputs."""
    if state is None:
        state, _ = _drive([(CAR_MPS,) * 4] * 100, accel, CoreState(), start)
        assert state.mode == Mode.STANDBY
        start = 100
    outs = []
    for k, wheels in enumerate(cycles, start):
        state, out = step(state, _inputs(k, wheels, accel), P)
        outs.append(out)
    return state, outs


def _spin(lead_per_cycle_mps, cycles):
    """The front wheels spin up by ``lead_per_cycle_mps`` a cycle, the car's speed unchanged."""
    return [(CAR_MPS + lead_per_cycle_mps * n,) * 2 + (CAR_MPS,) * 2 for n in range(1, cycles + 1)]


def test_wheelspin_under_full_throttle_is_no_fault():
    """The front wheels spin up at 1.83 m/s a cycle (the most the paper run shows on friction 0.3) to
    the DBC's 111 m/s and stay there: every cycle plausible, and the speed estimate stays the car's."""
    state, outs = _drive(_spin(1.83, 50) + [(111.0, 111.0, CAR_MPS, CAR_MPS)] * 200, accel=1.0)
    assert all(out.fault_flags == 0 and out.mode == Mode.STANDBY for out in outs)
    assert state.speed_mps == pytest.approx(CAR_MPS)


def test_a_spin_decaying_after_the_accelerator_is_released_is_no_fault():
    state, _ = _drive(_spin(1.5, 40), accel=1.0)
    lead = 60.0
    decay = [(CAR_MPS + lead - 0.5 * n,) * 2 + (CAR_MPS,) * 2 for n in range(1, 121)]
    _, outs = _drive(decay, accel=0.0, state=state, start=200)
    assert all(out.fault_flags == 0 for out in outs)


@pytest.mark.parametrize("accel, cycles, why", [
    (1.0, [(CAR_MPS,) * 3 + (CAR_MPS + 15.0,)], "the non-driven wheels disagree"),
    (0.0, [(CAR_MPS + 10.0,) * 2 + (CAR_MPS,) * 2], "the driven wheels run ahead with no torque"),
    (1.0, [(CAR_MPS + 15.0,) * 2 + (CAR_MPS,) * 2], "a lead no engine spins up in one cycle"),
    (1.0, [(CAR_MPS - 10.0,) * 2 + (CAR_MPS,) * 2], "a driven wheel slower than the car, unbraked"),
])
def test_wheel_speeds_that_no_road_and_no_torque_explain_fault(accel, cycles, why):
    _, outs = _drive(cycles, accel)
    assert outs[-1].fault_flags & SLIP, why
    assert outs[-1].mode == Mode.FAULT and outs[-1].throttle_limit_pct == 0.0


def test_a_spin_growing_long_after_the_accelerator_was_released_faults():
    """Within drive_memory_s the powertrain still pushes; after it, nothing spins a wheel up."""
    state, _ = _drive(_spin(1.0, 20), accel=1.0)
    hold = [(CAR_MPS + 20.0,) * 2 + (CAR_MPS,) * 2] * 80  # 0.8 s released, the spin held
    state, outs = _drive(hold, accel=0.0, state=state, start=200)
    assert not any(out.fault_flags for out in outs)
    _, outs = _drive([(CAR_MPS + 21.0,) * 2 + (CAR_MPS,) * 2], accel=0.0, state=state, start=300)
    assert outs[-1].fault_flags & SLIP


def test_a_reference_forged_low_in_one_step_stays_flagged():
    """Under full throttle a forger drops the non-driven wheels from 20 to 5 m/s (the front wheels true):
    it looks like wheelspin, but a lead of 15 m/s in a cycle is more than the engine can give, and it is
    held, so the forgery stays flagged for as long as it lasts instead of being learnt."""
    forged = [(CAR_MPS, CAR_MPS, 5.0, 5.0)] * 30
    state, outs = _drive(forged, accel=1.0)
    flagged = [bool(out.fault_flags & SLIP) for out in outs]
    assert flagged[1:] == [True] * 29  # the first cycle reads as braking (the free wheels fell): unchecked
    assert all(out.mode == Mode.FAULT for out in outs[1:])
    assert state.speed_mps > 15.0  # the estimate did not follow the forgery down
