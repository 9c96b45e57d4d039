"""The planar plant: steering actuator, straight-line motion, low speed and standstill, the friction
ellipse, robustness, and FMI 2 / FMI 3 / step-size agreement with the wheel turned.

Defaults (fmu_plant/README.md): wheelbase 2.7 m, CG 1.2 m behind the front axle, steering ratio 16,
steering lag 0.27 s, rate limit 0.4 rad/s, road-wheel limit 1.066 rad.
"""

import math

import numpy as np
import pytest

from tests.fmu.golden_longitudinal import SEQUENCES
from tests.fmu.plant_runner import run_plant, run_plant_at

PLANAR = ("x", "y", "yaw", "yaw_rate", "ay", "vx", "vy", "delta", "v", "a", "wheel_speed_fl", "wheel_speed_rl")
L, LR, RATIO, TAU, RATE = 2.7, 1.5, 16.0, 0.27, 0.4


def run(fmu, stop_s, step_s, schedule, params=None, version=2):
    return run_plant(fmu, version, stop_s, step_s, schedule, params, outputs=PLANAR)


# -- steering actuator --------------------------------------------------------------------------
def test_the_road_wheel_follows_the_steering_wheel_through_ratio_lag_and_rate_limit(fmu2):
    """A 1.6 rad steering-wheel step: 0.1 rad at the road wheel, 63.2 % of it after tau (first-order
    lag), never faster than the rate limit; 1 ms resolution."""
    r = run(fmu2, 2.0, 0.001, lambda t: {"steering_wheel_angle": 1.6})
    target = 1.6 / RATIO
    k_tau = int(round(TAU / 0.001))
    assert r["delta"][k_tau] == pytest.approx((1 - math.exp(-1)) * target, rel=0.02)
    assert r["delta"][-1] == pytest.approx(target, rel=1e-3)
    assert np.diff(r["delta"]).max() <= RATE * 0.001 * (1 + 1e-12)


def test_a_large_step_moves_at_the_rate_limit_and_stops_at_the_angle_limit(fmu2):
    r = run(fmu2, 4.0, 0.001, lambda t: {"steering_wheel_angle": 20.0}, {"steering_time_constant": 0.0})
    rates = np.diff(r["delta"]) / 0.001
    assert rates.max() == pytest.approx(RATE, rel=1e-9)
    assert r["delta"][-1] == 1.066  # 20 / 16 = 1.25 rad asked, limited to steering_angle_max
    assert r["delta"][int(round(1.0 / 0.001))] == pytest.approx(RATE * 1.0, rel=1e-9)


def test_the_ecu_request_is_a_road_wheel_angle_added_to_the_drivers(fmu2):
    params = {"steering_time_constant": 0.0}
    both = run(fmu2, 1.0, 0.01, lambda t: {"steering_wheel_angle": 0.8, "steer_request": -0.02}, params)
    assert both["delta"][-1] == pytest.approx(0.8 / RATIO - 0.02, abs=1e-12)
    alone = run(fmu2, 1.0, 0.01, lambda t: {"steer_request": 0.03}, params)
    assert alone["delta"][-1] == pytest.approx(0.03, abs=1e-12)


# -- straight ahead -----------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["random_inputs_random_steps", "low_friction"])
def test_with_the_wheel_straight_there_is_no_lateral_motion_at_all(fmu2, name):
    seq = SEQUENCES[name]
    lateral = ("y", "yaw", "yaw_rate", "ay", "vy", "delta")
    r = run_plant_at(fmu2, 2, seq.points_us, lambda t: {**seq.schedule(t), "steering_wheel_angle": 0.0},
                     seq.params, outputs=("v", *lateral))
    assert r["v"].max() > 5.0
    for col in lateral:
        assert not np.any(r[col]), f"{col} moved with the wheel straight"


def test_driving_straight_at_an_initial_heading_goes_along_it(fmu2):
    """yaw0 = 0.6 rad: the same distance as along x, along the heading (rounding only)."""
    schedule = lambda t: {"throttle": 1.0 if t < 4.0 else 0.0, "brake": 0.0 if t < 4.0 else 0.5}  # noqa: E731
    ahead = run(fmu2, 6.0, 0.01, schedule, {"x0": 5.0})
    turned = run(fmu2, 6.0, 0.01, schedule, {"x0": 5.0, "y0": -2.0, "yaw0": 0.6})
    s = ahead["x"] - 5.0
    np.testing.assert_allclose(turned["x"], 5.0 + s * math.cos(0.6), rtol=0, atol=1e-9)
    np.testing.assert_allclose(turned["y"], -2.0 + s * math.sin(0.6), rtol=0, atol=1e-9)
    np.testing.assert_array_equal(turned["v"], ahead["v"])
    assert (turned["yaw"] == 0.6).all()


# -- low speed and standstill -------------------------------------------------------------------
def test_at_walking_pace_the_car_drives_the_kinematic_circle(fmu2):
    """delta 0.3 rad at about 1.5 m/s: radius of the CG L / (tan(delta) cos(beta)), beta =
    atan(l_r tan(delta) / L) (CommonRoad KS); the tyres need almost no slip. Tolerance 0.5 %."""
    r = run(fmu2, 20.0, 0.01, lambda t: {"steering_wheel_angle": RATIO * 0.3, "throttle": 0.05})
    beta = math.atan(LR * math.tan(0.3) / L)
    radius = L / (math.tan(0.3) * math.cos(beta))
    assert 1.0 < r["v"][-1] < 2.5
    assert r["v"][-1] / r["yaw_rate"][-1] == pytest.approx(radius, rel=0.005)


def test_the_low_speed_switch_is_smooth(fmu2):
    """From rest with the wheel turned, through the kinematic-to-dynamic switch at 0.1 m/s: the yaw
    rate never jumps by more than 1e-3 rad/s between 1 ms samples."""
    r = run(fmu2, 3.0, 0.001, lambda t: {"steering_wheel_angle": RATIO * 0.3, "throttle": 0.05},
            {"steering_time_constant": 0.0})
    crossed = np.flatnonzero((r["v"][:-1] < 0.1) & (r["v"][1:] >= 0.1))
    assert crossed.size == 1
    assert np.abs(np.diff(r["yaw_rate"])).max() < 1e-3


def test_at_standstill_turning_the_wheel_moves_nothing_else(fmu2):
    r = run(fmu2, 5.0, 0.01, lambda t: {"steering_wheel_angle": 5.0 * math.sin(t)}, {"x0": 3.0, "y0": 1.0})
    assert abs(r["delta"]).max() > 0.25
    assert (r["x"] == 3.0).all() and (r["y"] == 1.0).all() and (r["yaw"] == 0.0).all()
    assert (r["yaw_rate"] == 0.0).all() and (r["v"] == 0.0).all() and (r["vy"] == 0.0).all()


def test_braking_to_a_stop_in_a_turn_then_resting_without_chatter(fmu2):
    r = run(fmu2, 8.0, 0.01, lambda t: {"steering_wheel_angle": RATIO * 0.05, "brake": 0.6 if t > 1.0 else 0.0},
            {"v0": 10.0})
    stopped = np.argmax(r["v"] == 0.0)
    assert 0 < r["t"][stopped] < 5.0
    after = slice(stopped + 1, None)
    for col in ("x", "y", "yaw"):
        assert (r[col][after] == r[col][stopped]).all(), col
    assert (r["yaw_rate"][after] == 0.0).all()


# -- friction ellipse and robustness ------------------------------------------------------------
def test_drive_force_on_the_front_axle_takes_lateral_grip_power_understeer(fmu2):
    """A wet-road circle at 12 m/s; opening the throttle of the front-driven car uses the front tyres'
    friction for drive, so the yaw rate falls below the kinematic v delta / L (friction ellipse)."""
    def ratio(throttle):
        r = run(fmu2, 3.0, 0.01, lambda t: {"steering_wheel_angle": RATIO * 0.08, "road_friction": 0.6,
                                            "throttle": 0.15 if t < 1.5 else throttle},
                {"v0": 12.0, "steering_time_constant": 0.0})
        return r["yaw_rate"][-1] / (r["v"][-1] * 0.08 / L)
    gentle, full = ratio(0.15), ratio(1.0)
    assert gentle > 0.98
    assert full < 0.85


def test_extreme_steering_on_snow_stays_finite(fmu2):
    """Full lock back and forth at 30 m/s on snow, full throttle: the car slides, and every output
    stays finite (the FMU would fail the step otherwise)."""
    r = run(fmu2, 10.0, 0.01, lambda t: {"steering_wheel_angle": 16.0 * math.sin(3 * t), "throttle": 1.0,
                                         "road_friction": 0.3}, {"v0": 30.0})
    assert all(np.isfinite(r[c]).all() for c in PLANAR)
    assert (r["v"] >= 0.0).all() and np.abs(r["vy"]).max() > 0.5


# -- FMI versions and step sizes ----------------------------------------------------------------
def slalom(t: float) -> dict[str, float]:
    """A steering sine with throttle, an ECU overlay and braking; held on a 50 ms grid so that every
    communication step below sees the same inputs."""
    t = math.floor(t / 0.05 + 1e-6) * 0.05
    return {"steering_wheel_angle": 0.8 * math.sin(1.5 * t), "throttle": 0.4 if t < 3.0 else 0.0,
            "brake": 0.0 if t < 4.0 else 0.4, "steer_request": 0.01 if 2.0 <= t < 2.5 else 0.0}


def test_fmi2_and_fmi3_and_whole_millisecond_steps_agree_bit_for_bit_with_the_wheel_turned(fmus):
    ref = run(fmus[2], 6.0, 0.05, slalom, {"v0": 15.0})
    assert np.abs(ref["y"]).max() > 1.0  # it really turns
    for version, step in ((3, 0.05), (2, 0.01), (2, 0.001)):
        other = run(fmus[version], 6.0, step, slalom, {"v0": 15.0}, version)
        stride = int(round(0.05 / step))
        for col in PLANAR:
            np.testing.assert_array_equal(other[col][::stride], ref[col], err_msg=f"FMI {version} {step} s: {col}")


def test_steps_that_split_the_grid_stay_close_with_the_wheel_turned(fmu2):
    """2.5 ms steps (inputs on a 50 ms grid, as in test_variable_step): within 5 mm, 1 mrad and
    1 mrad/s of the 1 ms trajectory over 6 s (measured: 0.3 mm, 0.02 mrad, 0.02 mrad/s)."""
    ref = run(fmu2, 6.0, 0.001, slalom, {"v0": 15.0})
    split = run(fmu2, 6.0, 0.0025, slalom, {"v0": 15.0})
    k_ref, k_split = np.arange(0, 6001, 50), np.arange(0, 2401, 20)
    assert np.abs(ref["y"]).max() > 5.0
    for col, tol in (("x", 0.005), ("y", 0.005), ("yaw", 1e-3), ("yaw_rate", 1e-3), ("delta", 1e-9)):
        worst = np.abs(split[col][k_split] - ref[col][k_ref]).max()
        assert worst <= tol, f"{col}: {worst} > {tol}"
