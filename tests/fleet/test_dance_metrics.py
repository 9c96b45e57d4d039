"""The dance figures from synthetic world rows: cleared, deadlock, time to clear."""

import pytest

from cosim.fleet.config import FleetSection
from cosim.fleet.dance_metrics import _cleared_at, _deadlock_s

ZONE = FleetSection(conflict_radius_m=5.0, approach_radius_m=20.0, progress_speed_mps=0.5)


def test_a_car_clears_when_it_leaves_the_zone_after_entering_it():
    xs = [-10.0, -4.0, 0.0, 4.0, 6.0, 9.0]
    ts = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
    assert _cleared_at(xs, [0.0] * 6, ts, ZONE) == 4.0


def test_a_car_that_stops_short_never_clears():
    assert _cleared_at([-30.0, -20.0, -10.0, -10.0], [0.0] * 4, [0, 1, 2, 3], ZONE) is None


def test_deadlock_counts_only_cycles_when_every_waiting_car_is_near_and_still():
    # two cars (x, y, yaw, speed each): both stopped near the zone for 3 rows, then car 0 moves
    rows = [(t * 0.01, -10.0, 0.0, 0.0, 0.2 if t < 3 else 2.0, 0.0, -10.0, 1.57, 0.0) for t in range(6)]
    assert _deadlock_s(rows, [None, None], ZONE) == pytest.approx(0.03)
    # car 0 has cleared from t = 0: only car 1 waits, still, so every row is deadlock
    assert _deadlock_s(rows, [0.0, None], ZONE) == pytest.approx(0.06)
    # far away: no deadlock
    far = [(r[0], -50.0, *r[2:]) for r in rows]
    assert _deadlock_s(far, [None, None], ZONE) == 0.0
