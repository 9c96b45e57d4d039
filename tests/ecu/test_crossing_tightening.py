"""Tightening against crossing vehicles (ecu.core.region.crossing) and the way-out rule (ecu.core.way_out)."""

import math

import pytest

from can_dbc.contract import enumeration
from ecu.core.params import CoreParams
from ecu.core.region import EgoState, TrackBox, decide
from ecu.core.region.crossing import crossing_proximity
from ecu.core.types import CoreState
from ecu.core.way_out import impatient, next_slow_cycles

CLASS = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}
EGO_SPEED = 8.0


def _proximity(track: TrackBox, way_out: str = "none") -> float:
    params = CoreParams(strategy="tightening")
    ego = EgoState(EGO_SPEED, 0.0, params.model_decel_mps2)
    decision = decide(ego, [track], None, params.region, steer=False)
    return crossing_proximity(decision, [track], EGO_SPEED, params.region, way_out)


def _crossing_car(side: float, size_class: str = "CAR") -> TrackBox:
    """A car 15 m ahead and 6 m to the side (``side`` +1 left, -1 right), driving toward our path at 8 m/s
    (velocities relative to the ego, as the contract carries them)."""
    return TrackBox(15.0, 6.0 * side, -EGO_SPEED, -8.0 * side, CLASS[size_class], 0.17)


def test_a_car_crossing_toward_our_path_raises_the_proximity_the_more_the_nearer():
    far, near = _proximity(_crossing_car(+1)), _proximity(TrackBox(10.0, 4.0, -EGO_SPEED, -8.0, CLASS["CAR"], 0.17))
    assert 0.0 < far < near
    assert _proximity(_crossing_car(-1)) > 0.0


@pytest.mark.parametrize("track, why", [
    (_crossing_car(+1, "PEDESTRIAN"), "a pedestrian: the contingency alone"),
    (_crossing_car(+1, "BICYCLE"), "a cyclist: the contingency alone"),
    (TrackBox(15.0, 3.5, -2.0 * EGO_SPEED, 0.0, CLASS["CAR"], 0.17), "oncoming in the next lane"),
    (TrackBox(5.0, 3.5, 3.0, 0.0, CLASS["CAR"], 0.17), "overtaking"),
    (TrackBox(15.0, -1.5, -EGO_SPEED, -6.0, CLASS["CAR"], 0.17), "a lead turning off to the right, leaving"),
    (TrackBox(15.0, 6.0, -EGO_SPEED, 0.0, CLASS["CAR"], 0.17), "a parked car"),
])
def test_what_does_not_cross_does_not_tighten(track, why):
    assert _proximity(track) == 0.0, why


def test_right_of_way_gives_way_to_the_right_only():
    assert _proximity(_crossing_car(-1), "right_of_way") == _proximity(_crossing_car(-1)) > 0.0
    assert _proximity(_crossing_car(+1), "right_of_way") == 0.0


def test_patience_counts_slow_cycles_near_something_and_ends_the_yield():
    params = CoreParams(way_out="right_of_way", way_out_patience_s=0.05)
    state = CoreState()
    for _ in range(5):
        assert not impatient(state, params)
        state = state._replace(slow_cycles=next_slow_cycles(state, 0.5, True, params))
    assert impatient(state, params)
    assert next_slow_cycles(state, 3.0, True, params) == 0  # going again: it gives way again
    assert next_slow_cycles(state, 0.5, False, params) == 0  # nothing near
    plain = CoreParams(way_out="none")
    assert next_slow_cycles(CoreState(slow_cycles=9), 0.5, True, plain) == 0 and not impatient(
        CoreState(slow_cycles=999), plain)


def test_the_rules_registry_matches_the_declared_choices():
    from ecu.core.params import CoreParams as P
    from ecu.core.region.crossing import WAY_OUT_RULES
    from ecu.settings import keys

    assert tuple(WAY_OUT_RULES) == keys(P)["way_out"].declared.choices
    assert math.isclose(P().way_out_patience_s, 1.5)


def _crossing_pair(d_west_m: float, d_south_m: float, speed_mps: float = 8.0) -> tuple[bool, bool]:
    """ORCA's split for two cars crossing at right angles, each seeing the other as its radar track: west
    (heading east) ``d_west_m`` before the crossing, south (heading north) ``d_south_m``; (west slows, south
    slows)."""
    from ecu.core.region.reciprocal import ours_to_slow

    region = CoreParams().region
    seen_by_west = TrackBox(d_west_m - 0.85, -d_south_m, -speed_mps, speed_mps, CLASS["CAR"], 0.17)
    seen_by_south = TrackBox(d_south_m - 0.85, d_west_m, -speed_mps, -speed_mps, CLASS["CAR"], 0.17)
    return ours_to_slow(seen_by_west, speed_mps, region), ours_to_slow(seen_by_south, speed_mps, region)


def test_orca_split_the_later_car_slows_and_the_earlier_goes_on():
    assert _crossing_pair(20.0, 25.0) == (False, True)
    assert _crossing_pair(25.0, 20.0) == (True, False)


def test_orca_split_in_the_symmetric_tie_both_slow():
    """The reciprocal dance RVO's authors report for symmetric encounters (planar-protocol-facts.md §8)."""
    assert _crossing_pair(20.0, 20.0) == (True, True)


def test_orca_normal_head_on_points_back_and_to_the_right():
    from ecu.core.region.reciprocal import outward_normal

    nx, ny = outward_normal((10.0, 0.0), (5.0, 0.0), 2.0, 5.0)
    assert nx < 0.0 and ny < 0.0 and math.isclose(math.hypot(nx, ny), 1.0)
    # beyond the horizon: the cut-off circle (centre p / tau = (20, 0)), its normal toward v
    assert outward_normal((100.0, 0.0), (1.0, 0.0), 2.0, 5.0) == pytest.approx((-1.0, 0.0))
