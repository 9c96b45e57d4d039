"""The pure-pursuit driver against its geometry (Coulter 1992) and in a closed loop with a
kinematic single-track model."""

import math

import numpy as np
import pytest

from cosim.world.path_following import (Path, PathError, Pose, PurePursuitParams, pursuit,
                                        steering_wheel_angle)

P = PurePursuitParams()  # wheelbase 2.7 m, rear axle 1.5 m behind the CG, ratio 16


def straight(y_m: float = 0.0, length_m: float = 200.0) -> Path:
    x = np.linspace(-50.0, length_m, 501)
    return Path.from_points(x, np.full_like(x, y_m))


def test_on_the_path_and_aligned_the_wheel_stays_straight():
    assert steering_wheel_angle(Pose(0.0, 0.0, 0.0), 20.0, straight(), P) == 0.0


@pytest.mark.parametrize("offset_m", [0.3, -1.2])
def test_beside_a_straight_path_it_steers_towards_it_by_the_pure_pursuit_arc(offset_m):
    """Car parallel to the path, offset e to its right: the goal point lies e to the left at
    look-ahead l, so delta = atan(L 2 e / l^2)."""
    r = pursuit(Pose(0.0, -offset_m, 0.0), 20.0, straight(), P)
    lookahead = 0.5 * 20.0
    assert r.lookahead_m == lookahead
    assert r.cross_track_m == pytest.approx(offset_m)
    expect = math.atan(2.7 * 2.0 * offset_m / lookahead**2)
    assert r.road_wheel_angle_rad == pytest.approx(expect, rel=1e-12)
    assert r.steering_wheel_angle_rad == pytest.approx(16.0 * expect, rel=1e-12)


@pytest.mark.parametrize("radius_m", [30.0, 120.0])
def test_on_a_circle_it_holds_the_kinematic_steering_angle(radius_m):
    """Rear axle on a circle, tangent to it: the pursuit arc is the circle, delta = atan(L / R)."""
    phi = np.linspace(-0.5 * math.pi, 1.0 * math.pi, 3000)
    path = Path.from_points(radius_m * np.cos(phi), radius_m * np.sin(phi))
    # rear axle at angle 0 on the circle, heading +y (counter-clockwise): the CG is 1.5 m ahead
    pose = Pose(radius_m, 1.5, math.pi / 2)
    delta = pursuit(pose, 15.0, path, P).road_wheel_angle_rad
    assert delta == pytest.approx(math.atan(2.7 / radius_m), rel=2e-3)


def test_lookahead_follows_speed_within_its_limits():
    path = straight()
    assert pursuit(Pose(0, 0, 0), 0.0, path, P).lookahead_m == P.lookahead_min_m
    assert pursuit(Pose(0, 0, 0), 30.0, path, P).lookahead_m == 15.0
    assert pursuit(Pose(0, 0, 0), 200.0, path, P).lookahead_m == P.lookahead_max_m


def test_the_angle_is_limited_to_the_road_wheel_limit():
    r = pursuit(Pose(0.0, -50.0, 0.0), 1.0, straight(), P)  # far to the right, slow: full lock
    assert r.road_wheel_angle_rad == P.max_road_wheel_angle_rad


def test_past_the_end_the_last_segment_is_extended():
    path = Path.from_points([0.0, 10.0], [0.0, 0.0])
    r = pursuit(Pose(20.0, -0.5, 0.0), 10.0, path, P)
    assert r.goal_y_m == 0.0 and r.goal_x_m > 20.0 and r.road_wheel_angle_rad > 0.0


@pytest.mark.parametrize("x, y, match", [([0.0], [0.0], ">= 2 points"), ([0.0, 1.0], [0.0, math.nan], "finite"),
                                         ([0.0, 0.0, 1.0], [0.0, 0.0, 0.0], "point 1 repeats")])
def test_bad_paths_are_refused(x, y, match):
    with pytest.raises(PathError, match=match):
        Path.from_points(x, y)


def test_bad_parameters_and_speed_are_refused():
    with pytest.raises(PathError, match="wheelbase_m"):
        PurePursuitParams(wheelbase_m=0.0)
    with pytest.raises(PathError, match="cg_to_rear_axle_m"):
        PurePursuitParams(cg_to_rear_axle_m=3.0)
    with pytest.raises(PathError, match="speed_mps"):
        pursuit(Pose(0, 0, 0), -1.0, straight(), P)


def kinematic_lane_change(speed_mps: float, stop_s: float, h_s: float = 0.01):
    """Kinematic single-track model about the CG (CommonRoad KS), steered by the driver every step."""
    x = np.linspace(-20.0, 400.0, 841)
    y = np.where(x < 40.0, 0.0, np.where(x > 80.0, 3.5, 1.75 * (1.0 - np.cos(math.pi * (x - 40.0) / 40.0))))
    path = Path.from_points(x, y)
    px, py, yaw, track = 0.0, 0.0, 0.0, []
    for _ in range(int(round(stop_s / h_s))):
        delta = steering_wheel_angle(Pose(px, py, yaw), speed_mps, path, P) / P.steering_ratio
        beta = math.atan(1.5 * math.tan(delta) / 2.7)
        px += h_s * speed_mps * math.cos(yaw + beta)
        py += h_s * speed_mps * math.sin(yaw + beta)
        yaw += h_s * speed_mps * math.cos(beta) * math.tan(delta) / 2.7
        track.append((px, py, yaw))
    return np.array(track)


def test_a_closed_loop_lane_change_settles_in_the_new_lane():
    track = kinematic_lane_change(speed_mps=15.0, stop_s=12.0)
    assert track[-1, 0] > 150.0
    assert abs(track[-1, 1] - 3.5) < 0.02 and abs(track[-1, 2]) < 1e-3  # in the lane, aligned
    assert track[:, 1].max() < 3.5 + 0.1  # no more than 10 cm overshoot
