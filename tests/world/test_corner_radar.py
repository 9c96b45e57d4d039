"""The rear corner radars (cosim.world.corner_radar): a car beside or behind, which the forward radar cannot
see, is reported in the forward radar's frame (x from the front bumper's centre, negative beside and behind)
at its point nearest that origin; the two sensors' lists merge into one, each object once, at most four."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from cosim.world.corner_radar import corner_params, merged
from cosim.world.geometry import BodyMotion, Box
from cosim.world.radar2d import EgoPose, ObjectTruth, Radar2DParams, RadarMount, RadarState, Scan, Track, radar_step

#: an ego 4.5 m long and 1.8 m wide whose pose point is its rear axle, 3.5 m behind the front bumper
BODY = SimpleNamespace(front_m=3.5, length_m=4.5, half_width_m=0.9)
FORWARD = Radar2DParams(mount=RadarMount(3.5), period_cycles=1, latency_cycles=0)
EGO = EgoPose(0.0, 0.0, 0.0, 10.0, 0.0)
LEFT, RIGHT = corner_params(FORWARD, BODY)


def car(i: int, x: float, y: float, vx: float = 10.0) -> ObjectTruth:
    return ObjectTruth(i, Box(x, y, 0.0, 4.0, 1.8), BodyMotion(vx, 0.0), "car")


def seen(params: Radar2DParams, *objects: ObjectTruth) -> tuple[Track, ...]:
    return radar_step(RadarState(), Scan(0, EGO, objects), params)[1]


def test_a_car_level_with_us_in_the_next_lane_is_seen_by_the_left_corner_radar_only():
    beside = car(1, 1.0, 3.5)  # its centre level with ours, in the lane to the left, at our speed
    assert seen(FORWARD, beside) == ()
    (t,) = seen(LEFT, beside)
    assert seen(RIGHT, beside) == ()
    # its box spans x -4.5..-0.5 from our front bumper: the point nearest the bumper's centre is its front corner
    assert (t.x_m, t.y_m, t.vx_mps, t.vy_mps) == pytest.approx((-0.5, 3.5 - 0.9, 0.0, 0.0))


def test_a_car_beside_our_front_half_is_seen_too():
    """No gap between the forward radar's +-45 degrees and the corner radars (the merge with the ramp 2 m back)."""
    ahead_beside = car(1, 3.5, 3.5)  # its box -2..2 m from our front bumper, its side 2.6 m to ours (52 deg)
    assert seen(FORWARD, ahead_beside) == () and len(seen(LEFT, ahead_beside)) == 1


def test_a_car_behind_in_our_lane_has_negative_x_and_closes_from_behind():
    behind = car(2, -15.0, 0.0, vx=14.0)  # 4 m/s faster than us
    tracks = seen(LEFT, behind) + seen(RIGHT, behind)
    assert tracks and all(t.x_m == pytest.approx(-15.0 + 2.0 - 3.5) for t in tracks)
    assert all(t.vx_mps == pytest.approx(4.0) for t in tracks)


def test_a_car_ahead_in_our_lane_is_the_forward_radars_alone():
    ahead = car(3, 30.0, 0.0)
    assert seen(LEFT, ahead) == () and seen(RIGHT, ahead) == () and len(seen(FORWARD, ahead)) == 1


def test_the_merged_list_has_each_object_once_most_urgent_first_at_most_the_slots():
    def track(i, x, existence, vx=0.0):
        return Track(i, x, 3.0, vx, 0.0, existence, "car")
    both = merged(((track(1, -5.0, 0.5), track(2, -30.0, 0.9, vx=5.0)), (track(1, -5.0, 0.75),)), 4)
    assert [(t.id, t.existence) for t in both] == [(2, 0.9), (1, 0.75)]  # 2 closes from behind: the most urgent
    many = merged((tuple(track(i, -10.0 - i, 0.5) for i in range(6)), ()), 4)
    assert [t.id for t in many] == [0, 1, 2, 3]


def test_the_sensors_take_the_forward_radars_latency_and_noise_each_with_a_seed_of_its_own():
    noisy = Radar2DParams(latency_cycles=2, noise_std=(0.1, 0.1, 0.2, 0.2), dropout_probability=0.1, seed=7)
    left, right = corner_params(noisy, BODY)
    assert (left.latency_cycles, left.noise_std, left.dropout_probability) == (2, noisy.noise_std, 0.1)
    assert {left.seed, right.seed, noisy.seed} == {7, 8, 9}
    assert left.mount.y_m == 0.9 and right.mount.y_m == -0.9 and left.mount.x_m == 3.5 - 4.5


def test_a_cyclist_crossing_at_56_degrees_is_seen_by_a_front_corner_radar_only():
    """A cyclist on a collision course at 15 km/h with us at 10 km/h keeps its bearing, atan(15/10) = 56 deg:
    outside the forward radar's +-45 deg, inside the left front corner's field (ncap_vru CBNA-*-10)."""
    front_left, front_right = corner_params(FORWARD, BODY, front=True)
    cyclist = ObjectTruth(4, Box(3.5 + 10.0, 15.0, -1.5708, 1.89, 0.5), BodyMotion(0.0, -4.17), "bicycle")
    assert seen(FORWARD, cyclist) == () and seen(front_right, cyclist) == ()
    (t,) = seen(front_left, cyclist)
    assert 9.0 < t.x_m < 10.5 and 14.0 < t.y_m < 15.0  # reported in the forward radar's frame, as its own tracks
    assert front_left.max_tracks == FORWARD.max_tracks and front_left.seed == FORWARD.seed + 3


def test_the_front_corners_see_no_further_than_the_forward_radar():
    """A scenario that uncovers an object by the forward radar's range (emergency_steering) uncovers it to them too."""
    near = Radar2DParams(mount=RadarMount(3.5), period_cycles=1, latency_cycles=0, max_range_m=30.0)
    assert all(p.max_range_m == 30.0 for p in corner_params(near, BODY, front=True))
    assert all(p.max_range_m == 80.0 for p in corner_params(FORWARD, BODY, front=True))
