"""A narrowing ahead and who passes it first (ecu.core.region.narrowing, StVO section 6)."""

import math

import pytest

from can_dbc.contract import enumeration
from ecu.core.params import CoreParams
from ecu.core.region import EgoState, TrackBox
from ecu.core.region.crossing import WAY_OUT_RULES
from ecu.core.region.narrowing import (
    NARROWING_RULES,
    TIE_S,
    find_narrowing,
    must_yield,
    Turn,
    in_corridor,
    room_for_two_m,
)

CLASS = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}
SPEED = 8.0
P = CoreParams(strategy="tightening", way_out="right_of_way")


def _parked(x_m: float, y_m: float) -> TrackBox:
    """A parked car's nearest point (x ahead of our bumper, y left), standing: it closes at our speed."""
    return TrackBox(x_m, y_m, -SPEED, 0.0, CLASS["UNKNOWN"], 0.17)


def _passage(entry_m: float = 30.0, inner_m: float = 2.25, lane_offset_m: float = 1.75) -> list[TrackBox]:
    """Two pairs of parked cars 10 m apart, their inner sides ``inner_m`` from the road's centre line, which is
    ``lane_offset_m`` to our left (we drive in our right-hand lane)."""
    return [_parked(entry_m + dx, lane_offset_m + side * inner_m) for dx in (0.0, 10.0) for side in (1, -1)]


def _oncoming(x_m: float, speed_mps: float = 8.0, y_m: float = 2.6) -> TrackBox:
    """A car coming toward us over ground at ``speed_mps`` in the lane left of ours (its nearest point)."""
    return TrackBox(x_m, y_m, -SPEED - speed_mps, 0.0, CLASS["CAR"], 0.17)


def _ego(speed_mps: float = SPEED) -> EgoState:
    return EgoState(speed_mps, 0.0, P.model_decel_mps2)


def test_parked_cars_on_both_sides_narrower_than_two_cars_make_a_narrowing():
    n = find_narrowing(_passage(), SPEED, P)
    assert n is not None
    assert n.entry_m == 30.0 and n.exit_m == pytest.approx(44.0)  # the far pair's near end plus a class length
    assert n.width_m == pytest.approx(4.5) and n.ours and n.theirs
    assert room_for_two_m(P) == pytest.approx(2 * (1.815 + 2 * (0.1 + 3 * 0.17)))


@pytest.mark.parametrize("tracks, why", [
    ([_parked(30.0, 4.0), _parked(40.0, 4.0)], "parked on one side only"),
    (_passage(inner_m=3.5), "a street 7 m wide between them: room for two"),
    ([TrackBox(30.0, t.y_m, -SPEED + 5.0, 0.0, t.size_class, 0.17) for t in _passage()], "moving, not parked"),
])
def test_what_is_not_a_narrowing(tracks, why):
    assert find_narrowing(tracks, SPEED, P) is None, why


def test_an_obstacle_only_in_the_other_lane_is_not_ours():
    """The parked cars leave our lane free (the centre line 1.75 m left, the right-hand ones beyond our lane's
    edge): the oncoming car must let us through, not we it."""
    n = find_narrowing(_passage(lane_offset_m=-0.5), SPEED, P)
    assert n is not None and not n.ours
    assert not must_yield(n, [*_passage(lane_offset_m=-0.5), _oncoming(60.0)], _ego(), P)


def test_the_car_that_reaches_the_narrowing_later_lets_the_other_through():
    """We are 30 m from the entry (3.75 s); the other is 16 m past the exit (2 s): it goes first."""
    n = find_narrowing(_passage(), SPEED, P)
    assert must_yield(n, [*_passage(), _oncoming(60.0)], _ego(), P)


def test_the_car_clearly_first_goes_on():
    """The other is 40 m past the exit (5 s) when we are 3.75 s from the entry."""
    n = find_narrowing(_passage(), SPEED, P)
    assert not must_yield(n, [*_passage(), _oncoming(84.0)], _ego(), P)


def test_in_the_tie_both_yield():
    """Arrivals within TIE_S: we 3.75 s from the entry, the other 3.75 s + 0.4 s from the far end."""
    n = find_narrowing(_passage(), SPEED, P)
    x = n.exit_m + SPEED * (30.0 / SPEED + TIE_S - 0.1)
    assert must_yield(n, [*_passage(), _oncoming(x)], _ego(), P)


def test_a_standing_car_on_the_other_side_is_not_oncoming_traffic():
    n = find_narrowing(_passage(), SPEED, P)
    assert not must_yield(n, [*_passage(), _oncoming(60.0, speed_mps=0.0)], _ego(), P)


def test_the_yield_tightens_toward_a_line_before_the_narrowing_and_only_under_right_of_way():
    """Stop short of the entry by narrowing_wait_m: the proximity grows as that line comes nearer; the other
    rules do not tighten at a narrowing."""
    rule = NARROWING_RULES["right_of_way"]
    near, far = (rule([*_passage(entry), _oncoming(entry + 30.0)], _ego(), P, Turn.NONE).proximity for entry in (25.0, 32.0))
    assert 0.0 < far < near <= 1.0
    assert NARROWING_RULES["none"]([*_passage(25.0), _oncoming(55.0)], _ego(), P, Turn.NONE).proximity == 0.0
    assert tuple(NARROWING_RULES) == tuple(WAY_OUT_RULES)


def test_once_in_the_narrowing_we_never_yield():
    """Its entry at or behind our bumper: we are in it and go on (the plant cannot back out)."""
    n = find_narrowing(_passage(), SPEED, P)
    assert must_yield(n, [*_passage(), _oncoming(60.0)], _ego(), P)
    assert not must_yield(n._replace(entry_m=0.0), [*_passage(), _oncoming(60.0)], _ego(), P)


def _standing_at(speed_mps: float):
    """Tracks as a car at ``speed_mps`` sees them, 2 m short of its waiting line: the passage's parked cars and a
    car standing 10 m beyond its far end in the lane left of ours (the other car of the standoff, on its side)."""
    entry = P.narrowing_wait_m + 2.0
    parked = [TrackBox(t.x_m, t.y_m, -speed_mps, 0.0, t.size_class, t.sigma_m) for t in _passage(entry)]
    return parked, TrackBox(entry + 24.0, 2.6, -speed_mps, 0.0, CLASS["CAR"], 0.17)


def test_two_cars_waiting_at_a_two_sided_narrowing_are_in_a_standoff_the_patience_counts():
    """Both wait before the narrowing: neither sees the other coming, so the rule keeps us waiting (a standoff)
    and says so, for the way-out patience to count; a car on the move, or our going, is no standoff."""
    from ecu.core.region.narrowing import standoff

    parked, partner = _standing_at(0.0)
    n = find_narrowing(parked, 0.0, P)
    assert standoff(n, [*parked, partner], _ego(0.0), P)
    answer = NARROWING_RULES["right_of_way"]([*parked, partner], _ego(0.0), P, Turn.NONE)
    assert answer.standoff and answer.proximity > 0.0
    assert not standoff(n, parked, _ego(0.0), P)  # nobody waits on the other side
    going = P.way_out_slow_speed_mps + 0.5
    parked_fast, partner_fast = _standing_at(going)
    assert not standoff(find_narrowing(parked_fast, going, P), [*parked_fast, partner_fast], _ego(going), P)
    creeping, _ = _standing_at(1.0)  # we creep at 1 m/s; it comes at 4 m/s: we yield, and that is no standoff
    answer = NARROWING_RULES["right_of_way"]([*creeping, partner._replace(vx_mps=-5.0)], _ego(1.0), P, Turn.NONE)
    assert answer.proximity > 0.0 and not answer.standoff


def test_a_one_sided_narrowing_is_no_standoff():
    """Only our side is blocked: the other car has the right to go and does not wait for us (StVO section 6)."""
    from ecu.core.region.narrowing import standoff

    parked = [TrackBox(x, y, 0.0, 0.0, CLASS["UNKNOWN"], 0.17) for x in (30.0, 40.0) for y in (-0.4, 5.5)]
    partner = TrackBox(54.0, 2.6, 0.0, 0.0, CLASS["CAR"], 0.17)
    n = find_narrowing(parked, 0.0, P)
    assert n is not None and n.ours and not n.theirs
    assert not standoff(n, [*parked, partner], _ego(0.0), P)


def _rotated(tracks: list[TrackBox], angle_rad: float) -> list[TrackBox]:
    """The tracks as a car whose heading is ``angle_rad`` to the left of the road's sees them (positions only)."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return [t._replace(x_m=c * t.x_m + s * t.y_m, y_m=-s * t.x_m + c * t.y_m) for t in tracks]


def test_the_corridor_follows_the_passage_not_our_heading():
    """Steering toward the gap (5 degrees left of the road), a car coming through the passage from 70 m lies
    metres to our right, outside our heading's lanes; it is still in the passage's corridor, and we yield."""
    angle = math.radians(5.0)
    passage, other = _rotated(_passage(20.0), angle), _rotated([_oncoming(70.0, speed_mps=16.0)], angle)[0]
    n = find_narrowing(passage, SPEED, P)
    assert other.y_m < -0.5 * P.lane_width_m  # outside the window of our heading's lanes
    assert n.centre_slope == pytest.approx(-math.tan(angle), abs=0.01)
    assert in_corridor(other, n, P)
    assert not in_corridor(other._replace(y_m=other.y_m - 2.0 * P.lane_width_m), n, P)
    assert must_yield(n, [*passage, other], _ego(), P)


def test_taking_a_turn_passes_a_standoff_but_backs_off_from_a_car_on_the_move():
    """Impatient (TAKING), we no longer wait for the car standing on the other side; if it comes too, the turn
    is contested and we yield. Only a car taking or having given back its turn sees a contest."""
    rule = NARROWING_RULES["right_of_way"]
    parked, partner = _standing_at(0.0)
    assert rule([*parked, partner], _ego(0.0), P, Turn.TAKING).proximity == 0.0
    coming = partner._replace(vx_mps=-2.0)
    taking = rule([*parked, coming], _ego(0.0), P, Turn.TAKING)
    assert taking.contested and taking.proximity > 0.0 and taking.found
    assert rule([*parked, coming], _ego(0.0), P, Turn.BACKED_OFF).contested
    assert not rule([*parked, coming], _ego(0.0), P, Turn.NONE).contested
    assert not rule([t for t in parked if t.y_m > 0.0], _ego(0.0), P, Turn.TAKING).found  # one side: none
