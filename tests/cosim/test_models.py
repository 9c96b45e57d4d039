"""Driver and radar models (seeded)."""

import numpy as np
import pytest

from can_dbc.codec import encode_payload
from cosim.world.driver_models import make_driver
from cosim.world.radar_model import RadarModel
from cosim.scenarios.config import DriverConfig, RadarConfig


def test_full_throttle_ignores_everything():
    d = make_driver(DriverConfig(model="full_throttle"))
    assert d(0.0, 0.0, 0.0) == d(12.0, 220.0, 30.0)
    assert d(1.0, 1.0, 1.0).accel_pct == 100.0 and d(1.0, 1.0, 1.0).brake_pct == 0.0


def test_cruise_holds_speed_with_p_law():
    d = make_driver(DriverConfig(model="cruise", set_speed_mps=20.0, gain_pct_per_mps=10.0))
    assert d(0, 0, 18.0).accel_pct == pytest.approx(20.0)
    slow = d(0, 0, 23.0)
    assert slow.accel_pct == 0.0 and slow.brake_pct == pytest.approx(30.0)


def test_scripted_interpolates_over_position():
    d = make_driver(DriverConfig(model="scripted", over="position", points=((0.0, 0.0, 0.0), (100.0, 50.0, 10.0))))
    p = d(99.0, 50.0, 0.0)
    assert (p.accel_pct, p.brake_pct) == pytest.approx((25.0, 5.0))
    assert d(0.0, 500.0, 0.0).accel_pct == 50.0  # held beyond the last point


def _track_series(cfg, seed, n=40):
    radar = RadarModel(cfg, np.random.default_rng(seed))
    out = []
    for i in range(n):
        radar.sample(100.0 - i, -10.0)
        out.append(radar.measure())
    return out


def test_radar_is_seeded_and_noisy():
    cfg = RadarConfig(range_noise_std_m=0.5, range_rate_noise_std_mps=0.2)
    a, b, c = _track_series(cfg, 7), _track_series(cfg, 7), _track_series(cfg, 8)
    assert a == b
    assert a != c
    errors = np.array([t.range_m - (100.0 - i) for i, t in enumerate(a)])
    assert 0.2 < errors.std() < 1.0


def test_radar_latency_max_range_and_dropout():
    late = _track_series(RadarConfig(latency_s=0.05), 1)
    assert not late[4].valid and late[5].range_m == pytest.approx(100.0)  # 5 cycles old
    far = RadarModel(RadarConfig(max_range_m=50.0), np.random.default_rng(0))
    far.sample(60.0, 0.0)
    assert not far.measure().valid
    far.sample(40.0, -3.0)
    t = far.measure()
    assert t.valid and t.range_m == 40.0 and t.range_rate_mps == -3.0
    dropped = _track_series(RadarConfig(dropout_probability=0.5), 3, n=400)
    share = sum(not t.valid for t in dropped) / len(dropped)
    assert 0.4 < share < 0.6


def test_radar_does_not_report_an_object_beyond_the_contracts_lateral_range():
    """ObjectTrack.ObjectLateral carries +-20 m: an object further to the side is outside the field the
    contract gives the radar, and is not reported (it stopped the run with a SignalError before)."""
    radar = RadarModel(RadarConfig(), np.random.default_rng(0))
    for lateral_m, reported in ((-22.0, False), (20.0, True), (-20.0, True), (20.5, False)):
        radar.sample(30.0, -5.0, lateral_m)
        t = radar.measure()
        assert t.valid is reported, lateral_m
        if reported:
            assert t.lateral_m == lateral_m
            encode_payload("ObjectTrack", t.signals(), 0)  # encodable as the DBC declares
