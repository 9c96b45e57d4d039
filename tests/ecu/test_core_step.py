"""The whole core cycle: contingency, fault handling and holding, determinism."""


from ecu.core import CoreInputs, CoreParams, CoreState, FaultFlag, Mode, step

#: objects appear here from one cycle to the next, so track confirmation (tests/ecu/test_track_confirmation.py)
#: is off: every valid report confirms itself
P = CoreParams(strategy="none", track_confirm_reports=1)


def fresh(t, speed=20.0, range_m=None, accel=1.0, brake=0.0):
    return CoreInputs(t_s=t, wheel_speeds_mps=(speed,) * 4, accel_pedal=accel, brake_pedal=brake,
                      object_valid=range_m is not None, object_range_m=range_m or 0.0,
                      object_range_rate_mps=-speed, wheel_rx_t_s=t, driver_rx_t_s=t, object_rx_t_s=t)


def run(inputs_at, cycles, state=None, k0=0, params=P):
    state = state or CoreState()
    outs = []
    for k in range(k0, k0 + cycles):
        state, out = step(state, inputs_at(k * 0.01), params)
        outs.append(out)
    return state, outs


def test_startup_is_fault_with_throttle_zero_then_standby():
    state, outs = run(lambda t: CoreInputs(t_s=t), 3)
    assert all(o.mode == Mode.FAULT and o.throttle_limit_pct == 0.0 for o in outs)
    assert outs[0].fault_flags == 0b00111
    state, outs = run(lambda t: fresh(t), P.fault_recovery_cycles, state, 3)
    assert [o.mode for o in outs][-2:] == [Mode.FAULT, Mode.STANDBY]


def test_violation_gives_contingency_and_release_when_disjoint_again():
    state, _ = run(lambda t: fresh(t, range_m=200.0), 12)
    state, out = step(state, fresh(0.12, range_m=29.5), P)  # d + 2 = 29.73 > 29.5
    assert (out.mode, out.throttle_limit_pct, out.brake_decel_request_mps2) == (Mode.CONTINGENCY, 0.0, 15.0)
    assert not out.disjoint
    state, out = step(state, fresh(0.13, range_m=30.0), P)  # no hysteresis: the dance
    assert out.mode == Mode.STANDBY and not out.override_active


def test_contingency_held_through_wheel_timeout_until_estimated_stop():
    state, _ = run(lambda t: fresh(t, range_m=200.0), 12)
    state, out = step(state, fresh(0.12, range_m=20.0), P)
    assert out.mode == Mode.CONTINGENCY
    # wheel speeds stop; the radar (valid) sees the car slow down at D, as the real one does
    # (degraded mode keeps braking while valid radar data still shows the car closing)
    stale = lambda t: fresh(t, range_m=20.0)._replace(
        wheel_rx_t_s=0.12, object_range_rate_mps=-max(0.0, 20.0 - 8.1 * (t - 0.12)))
    state, outs = run(stale, 400, state, 13)
    faulted = [o for o in outs if o.mode == Mode.FAULT]
    assert faulted and faulted[0].fault_flags & (1 << FaultFlag.WHEEL_SPEED_TIMEOUT)
    braking = [o.brake_decel_request_mps2 for o in faulted]
    assert braking[0] == P.contingency_decel_mps2 and braking[-1] == 0.0  # released only once the estimate stops
    stop_cycles = sum(1 for b in braking if b == P.contingency_decel_mps2)
    assert stop_cycles * 0.01 >= 20.0 / 8.1 - 0.1  # dead-reckoned at D: at least the real stop
    assert all(o.throttle_limit_pct == 0.0 for o in faulted)


def test_no_new_braking_from_invalid_data():
    state, _ = run(lambda t: fresh(t, range_m=200.0), 12)
    stale = lambda t: fresh(t, range_m=5.0)._replace(object_rx_t_s=0.11, object_e2e_score=5)
    state, outs = run(stale, 30, state, 12)
    assert all(o.mode == Mode.FAULT and o.brake_decel_request_mps2 == 0.0 for o in outs)
    assert outs[-1].fault_flags & (1 << FaultFlag.E2E)


def test_non_finite_inputs_are_an_internal_fault_not_a_crash():
    state, _ = run(lambda t: fresh(t), 12)
    state, out = step(state, fresh(0.12)._replace(object_range_m=float("nan"), object_valid=True), P)
    assert out.mode == Mode.FAULT and out.fault_flags & (1 << FaultFlag.INTERNAL)
    assert out.throttle_limit_pct == 0.0


def test_same_inputs_same_outputs():
    a = run(lambda t: fresh(t, speed=15 + t, range_m=60 - 10 * t), 200, params=CoreParams())
    b = run(lambda t: fresh(t, speed=15 + t, range_m=60 - 10 * t), 200, params=CoreParams())
    assert a == b
