"""The 2-D radar: field of view, nearest point, relative velocity, latency, noise, existence, frame budget."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosim.world.geometry import BodyMotion, Box
from cosim.world.radar2d import EgoPose, ObjectTruth, Radar2DParams, RadarMount, RadarState, Scan, radar_step

STILL = BodyMotion(0.0, 0.0)
EGO = EgoPose(0.0, 0.0, 0.0, 0.0, 0.0)
NOW = Radar2DParams(period_cycles=1, latency_cycles=0)


def car(i: int, x: float, y: float, yaw: float = 0.0, motion: BodyMotion = STILL) -> ObjectTruth:
    return ObjectTruth(i, Box(x, y, yaw, 4.0, 2.0), motion, "car")


def report(objects, params=NOW, ego=EGO, k=0, state=RadarState()):
    return radar_step(state, Scan(k, ego, tuple(objects)), params)[1]


def test_the_reported_point_is_the_nearest_point_in_sensor_axes():
    (t,) = report([car(1, 20.0, 0.0)])
    assert (t.x_m, t.y_m) == pytest.approx((18.0, 0.0))
    (t,) = report([car(1, 20.0, 0.0)], Radar2DParams(RadarMount(3.5, 0.0), period_cycles=1, latency_cycles=0))
    assert (t.x_m, t.y_m) == pytest.approx((14.5, 0.0))  # a radar behind the front grille of a 3.5 m-long overhang
    # the ego heading north: an object 20 m north is straight ahead
    (t,) = report([car(1, 0.0, 20.0, math.pi / 2)], ego=EgoPose(0.0, 0.0, math.pi / 2, 0.0, 0.0))
    assert (t.x_m, t.y_m) == pytest.approx((18.0, 0.0))
    # beside the car, rotated: nearest point is a corner of the object
    (t,) = report([car(1, 10.0, 5.0)])
    assert (t.x_m, t.y_m) == pytest.approx((8.0, 4.0))


def test_field_of_view_and_range():
    wide = 90.0  # ±45 deg
    assert report([car(1, 10.0, 8.0)])  # the centre at 38.7 deg
    assert not report([car(1, 10.0, 16.0)])  # every corner beyond 45 deg (the lowest at 51 deg)
    # the centre outside (47.7 deg), a corner inside: the box overlaps the field of view
    straddling = car(1, 11.0, 12.1)
    assert math.degrees(math.atan2(12.1, 11.0)) > wide / 2 and report([straddling])
    assert not report([car(1, -10.0, 0.0)])  # behind
    assert report([car(1, 201.9, 0.0)])  # nearest point 199.9 m
    assert not report([car(1, 202.1, 0.0)])
    assert report([car(1, 10.0, 8.0)], Radar2DParams(field_of_view_deg=360.0, period_cycles=1, latency_cycles=0))


def test_relative_velocity_counts_the_sensors_own_motion():
    ego = EgoPose(0.0, 0.0, 0.0, 20.0, 0.0, 0.5)  # 20 m/s, turning left at 0.5 rad/s
    mount = RadarMount(2.0, 0.0)  # 2 m ahead of the reference point: it moves (20, 1) m/s
    (t,) = report([car(1, 30.0, 0.0, motion=BodyMotion(10.0, 0.0))],
                  Radar2DParams(mount, period_cycles=1, latency_cycles=0), ego)
    assert (t.vx_mps, t.vy_mps) == pytest.approx((-10.0, -1.0))
    assert t.ttc_s == pytest.approx(26.0 / 10.0)


def test_report_cycles_and_latency_in_whole_cycles():
    params = Radar2DParams(period_cycles=5, latency_cycles=10)
    state, out = RadarState(), []
    for k in range(21):
        obj = car(1, 50.0 - k * 0.1, 0.0)  # closing 0.1 m per cycle
        state, tracks = radar_step(state, Scan(k, EGO, (obj,)), params)
        out.append(tracks)
    assert [k for k, tr in enumerate(out) if tr is not None] == [0, 5, 10, 15, 20]
    assert out[0] == () and out[5] == ()  # nothing 10 cycles old yet
    assert out[10][0].x_m == pytest.approx(48.0) and out[20][0].x_m == pytest.approx(48.0 - 1.0)


def test_existence_grows_with_confirmations_and_resets_out_of_view():
    state, seen = RadarState(), []
    for k in range(5):
        x = 20.0 if k != 3 else -20.0  # out of view at k = 3
        state, tracks = radar_step(state, Scan(k, EGO, (car(7, x, 0.0),)), NOW)
        seen.append(tracks[0].existence if tracks else None)
    assert seen == [0.5, 0.75, 0.875, None, 0.5]


def test_noise_is_seeded_gaussian_and_deterministic():
    params = Radar2DParams(period_cycles=1, latency_cycles=0, noise_std=(0.5, 0.2, 1.0, 0.1), seed=3)
    obj = car(1, 30.0, 0.0)
    samples = np.array([report([obj], params, k=k)[0][1:5] for k in range(3000)])
    np.testing.assert_allclose(samples.mean(axis=0), (28.0, 0.0, 0.0, 0.0), atol=0.05)
    np.testing.assert_allclose(samples.std(axis=0), params.noise_std, rtol=0.06)
    assert report([obj], params, k=17) == report([obj], params, k=17)
    assert report([obj], params, k=17) != report([obj], params.__class__(**{**_fields(params), "seed": 4}), k=17)
    # another object, out of view and with a higher id, does not change this one's noise
    assert report([obj, car(2, -30.0, 0.0)], params, k=17)[0] == report([obj], params, k=17)[0]


def _fields(params: Radar2DParams) -> dict:
    return {name: getattr(params, name) for name in params.__slots__}


def test_dropouts_at_the_given_probability():
    params = Radar2DParams(period_cycles=1, latency_cycles=0, dropout_probability=0.3, seed=1)
    reported = sum(bool(report([car(1, 30.0, 0.0)], params, k=k)) for k in range(4000))
    assert reported / 4000 == pytest.approx(0.7, abs=0.025)


def test_the_frame_budget_keeps_the_most_urgent_tracks():
    params = Radar2DParams(period_cycles=1, latency_cycles=0, max_tracks=3)
    standing = [car(i, 15.0 + 10.0 * i, 3.0 * (-1) ** i) for i in range(1, 7)]  # 6 not closing, 25..75 m
    closing_far = car(20, 90.0, 0.0, math.pi, BodyMotion(-20.0, 0.0))  # 88 m at 20 m/s: TTC 4.4 s
    closing_near = car(21, 60.0, -3.5, math.pi, BodyMotion(-15.0, 0.0))  # about 58 m at 15 m/s: TTC 3.9 s
    tracks = report([*standing, closing_far, closing_near], params)
    assert [t.id for t in tracks] == [21, 20, 1]  # by TTC, then the nearest of the rest
    assert len(report(standing, params)) == 3 and [t.id for t in report(standing, params)] == [1, 2, 3]


def test_bad_parameters_are_refused_by_name():
    with pytest.raises(ValueError, match="max_range_m=-1"):
        Radar2DParams(max_range_m=-1.0)
