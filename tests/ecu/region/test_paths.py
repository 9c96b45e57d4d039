"""The followable paths: the friction-circle stopping distance, the family's limits and symmetry."""

import math

import numpy as np
import pytest

from ecu.core import CoreParams
from ecu.core.region import EgoState, region_params
from ecu.core.region.paths import DRIVER, FIRST_STEER, LANE, NOMINAL, braking_m, path_family

P = region_params(CoreParams())


def _integrate_braking(v_h, kappa, friction, ds=1e-4):
    """Reference: Euler steps of v dv/ds = -sqrt(A^2 - (v^2 kappa)^2) until v = 0."""
    u, s = v_h * v_h, 0.0
    while u > 0.0:
        u -= 2.0 * math.sqrt(max(0.0, friction ** 2 - (kappa * u) ** 2)) * ds
        s += ds
    return s


@pytest.mark.parametrize("v_h, kappa", [(20.0, 0.0), (20.0, 0.01), (15.0, 0.03), (8.0, 0.1)])
def test_braking_distance_in_the_friction_circle_matches_integration(v_h, kappa):
    s, feasible = braking_m(np.array([v_h]), np.array([kappa]), 8.1)
    assert feasible[0]
    assert s[0] == pytest.approx(_integrate_braking(v_h, kappa, 8.1), abs=2e-3)
    assert s[0] >= v_h * v_h / (2 * 8.1)  # turning never shortens the stop


def test_a_curve_beyond_the_friction_circle_is_not_followable():
    _, feasible = braking_m(np.array([20.0, 20.0]), np.array([8.0 / 400, 8.2 / 400]), 8.1)
    assert feasible.tolist() == [True, False]


def test_family_is_symmetric_and_within_the_lateral_limit():
    paths = path_family(EgoState(20.0, 0.0, 8.1), 0.0, P)
    steer = paths.curvature_1pm[FIRST_STEER:]
    assert np.array_equal(steer, -steer[::-1]) and steer[len(steer) // 2] == 0.0
    assert np.all(np.abs(steer) * paths.hold_speed_mps[FIRST_STEER:] ** 2 <= P.emergency_lat_accel_max_mps2 + 1e-12)
    assert np.allclose(paths.position[FIRST_STEER:], np.conj(paths.position[FIRST_STEER:][::-1]))
    assert np.allclose(paths.stop_m[FIRST_STEER:], paths.stop_m[FIRST_STEER:][::-1])


def test_low_speed_family_stays_within_the_steering_angle_limit():
    paths = path_family(EgoState(2.0, 0.0, 8.1), 0.0, P)
    limit = math.tan(P.steer_angle_max_rad) / P.wheelbase_m
    assert np.max(np.abs(paths.curvature_1pm)) == pytest.approx(limit)
    assert len(set(np.round(paths.curvature_1pm[FIRST_STEER:], 12))) == P.steer_paths  # no collapsed rows


def test_driver_rows_follow_the_current_curvature_from_yaw_rate():
    ego = EgoState(10.0, 0.0, 8.1, yaw_rate_radps=0.5, road_wheel_angle_rad=math.atan(0.05 * P.wheelbase_m))
    paths = path_family(ego, 0.0, P)
    assert paths.curvature_1pm[DRIVER] == paths.curvature_1pm[NOMINAL] == pytest.approx(0.05)
    # the last pose lies on the circle of radius 20 m through the origin, centre (0, 20)
    assert np.allclose(np.abs(paths.position[DRIVER] - 20j), 20.0)
    assert paths.curvature_1pm[LANE] == 0.0


@pytest.mark.parametrize("wheel_curvature", [0.005, 0.0, -0.002])
def test_driver_rows_reach_the_wheels_curvature_from_the_yaw_rates(wheel_curvature):
    """At a curve's entry the wheel leads the yaw rate: the driver's path keeps kappa_0 over the lead-in of an ECU
    path (hold, steering lag, ramp), then the wheel's curvature; with the wheel straight it straightens."""
    k0, speed = 0.0015, 19.3
    ego = EgoState(speed, 0.0, 8.1, k0 * speed, math.atan(wheel_curvature * P.wheelbase_m))
    paths = path_family(ego, 0.0, P, steering=False)
    assert paths.curvature_1pm[DRIVER] == paths.curvature_1pm[NOMINAL] == pytest.approx(wheel_curvature)
    lead = paths.hold_m[DRIVER] + speed * P.steer_lag_s + speed * abs(wheel_curvature - k0) / (
        2.0 * P.steer_rate_max_radps / P.wheelbase_m)
    s = paths.stop_m[DRIVER] * P.sample_fractions
    on_k0 = s <= lead
    assert on_k0.any() and not on_k0.all()
    assert np.allclose(np.abs(paths.position[DRIVER][on_k0] - 1j / k0), 1.0 / k0)  # the yaw rate's circle
    heading = np.angle(paths.heading[DRIVER][~on_k0])
    assert np.allclose(heading, k0 * lead + wheel_curvature * (s[~on_k0] - lead))  # then the wheel's


def test_at_standstill_the_wheel_angle_gives_the_curvature():
    paths = path_family(EgoState(0.0, 0.0, 8.1, road_wheel_angle_rad=0.2), 0.0, P, steering=False)
    assert paths.curvature_1pm[DRIVER] == pytest.approx(math.tan(0.2) / P.wheelbase_m)
    assert paths.stop_m[DRIVER] == paths.stop_m[LANE] == 0.0 < paths.stop_m[NOMINAL]  # full throttle moves


def test_steering_paths_keep_the_current_curvature_over_the_lead_in():
    """Hold t_h and steering lag tau at kappa_0 = 0: the first metres are straight."""
    paths = path_family(EgoState(20.0, 0.0, 8.1), 0.0, P)
    lead = 20.0 * (P.hold_time_s + P.steer_lag_s)
    s = paths.stop_m[FIRST_STEER] * P.sample_fractions
    straight = s <= lead
    assert straight.any() and np.all(paths.position[FIRST_STEER][straight].imag == 0.0)
    assert np.all(paths.position[FIRST_STEER][~straight].imag < 0.0)


def test_a_jerk_limit_lengthens_the_lead_in():
    free = path_family(EgoState(20.0, 0.0, 8.1), 0.0, P)
    limited = path_family(EgoState(20.0, 0.0, 8.1), 0.0, region_params(CoreParams(), emergency_lat_jerk_max_mps3=5.0))
    assert abs(limited.position[-1, -1].imag) < abs(free.position[-1, -1].imag)
