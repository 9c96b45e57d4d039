"""``contingency_release_ratio``: a contingency holds until the stopping path clears with margin (issue 14)."""

from ecu.core import CoreInputs, CoreParams, CoreState, Mode, step

DT = 0.01


def _run(ratio: float, ranges_m: list[float], release_speed_mps: float = 1000.0) -> list[Mode]:
    params = CoreParams(strategy="none", contingency_release_ratio=ratio,
                        contingency_release_speed_mps=release_speed_mps)
    state, modes = CoreState(), []
    for k, range_m in enumerate(ranges_m):
        t = k * DT
        inputs = CoreInputs(t_s=t, wheel_speeds_mps=(10.0,) * 4, accel_pedal=1.0, object_valid=True,
                            object_range_m=range_m, object_range_rate_mps=-10.0,
                            wheel_rx_t_s=t, driver_rx_t_s=t, object_rx_t_s=t)
        state, out = step(state, inputs, params)
        modes.append(out.mode)
    return modes


def test_ratio_one_releases_as_soon_as_disjoint_and_a_larger_ratio_holds():
    # stopping distance at 10 m/s, full throttle held 0.11 s, D = 8.1 m/s^2: about 8.0 m (+ 2 m standoff)
    ranges = [100.0] * 15 + [9.0] * 5 + [11.0] * 5
    plain, held = _run(1.0, ranges), _run(1.5, ranges)
    assert plain[19] is Mode.CONTINGENCY and held[19] is Mode.CONTINGENCY
    assert plain[-1] is Mode.STANDBY  # 11 m clears 8 + 2
    assert held[-1] is Mode.CONTINGENCY  # 1.5 x 8 + 2 = 14 m > 11 m: still held


def test_release_speed_holds_the_contingency_until_the_car_is_slow_enough():
    ranges = [100.0] * 15 + [9.0] * 5 + [30.0] * 5
    assert _run(1.0, ranges)[-1] is Mode.STANDBY
    assert _run(1.0, ranges, release_speed_mps=0.1)[-1] is Mode.CONTINGENCY  # still 10 m/s
