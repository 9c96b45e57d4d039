"""The way-out patience and its back-off (ecu.core.way_out)."""

import pytest

from ecu.core.params import CoreParams
from ecu.core.planar import RegionCycle
from ecu.core.region.decision import Contingency, RegionDecision
from ecu.core.region.narrowing import Turn
from ecu.core.types import CoreState
from ecu.core.way_out import backoff_fraction, next_way_out, patience_s, turn

P = CoreParams(strategy="tightening", way_out="right_of_way", way_out_patience_s=2.0, way_out_seed=7)


def _Region(contested: bool, at_narrowing: bool = True, proximity: float = 0.5) -> RegionCycle:
    """A region cycle with what the back-off reads: the proximity, contested, and whether a narrowing is ahead
    (the rest is not read; a real RegionCycle, as the compiled core checks its argument's type)."""
    decision = RegionDecision(Contingency.DRIVER_PATH, 0, 0.0, 0.0, 0.0, 0.0, 0.0, True, 0.0, proximity,
                              None, None, None)  # type: ignore[arg-type]
    return RegionCycle(None, decision, True, 0.0, False, contested, at_narrowing)  # type: ignore[arg-type]


def test_the_draws_are_seeded_uniform_and_differ_per_seed_and_back_off():
    draws = [backoff_fraction(7, n) for n in range(1, 200)]
    assert draws == [backoff_fraction(7, n) for n in range(1, 200)]
    assert all(0.0 <= d < 1.0 for d in draws) and 0.4 < sum(draws) / len(draws) < 0.6
    assert backoff_fraction(7, 1) != backoff_fraction(8, 1)


def test_a_contested_turn_backs_off_and_waits_a_fresh_fraction_of_the_patience():
    waited = CoreState(slow_cycles=round(2.0 / P.cycle_s))
    assert turn(waited, P) == Turn.TAKING
    slow, backoffs = next_way_out(waited, 0.5, _Region(contested=True), True, P)
    assert (slow, backoffs) == (0, 1)
    after = CoreState(slow_cycles=0, way_out_backoffs=1)
    assert turn(after, P) == Turn.BACKED_OFF
    assert patience_s(after, P) == pytest.approx(2.0 * backoff_fraction(7, 1))
    assert patience_s(CoreState(), P) == 2.0
    # not contested: the turn goes on, counted as before
    assert next_way_out(waited, 0.5, _Region(contested=False), True, P)[1] == 0


def test_the_back_offs_are_kept_while_slow_or_before_the_narrowing_and_forgotten_once_past_it():
    backed = CoreState(way_out_backoffs=2)
    going = P.way_out_slow_speed_mps + 1.0
    assert next_way_out(backed, 0.5, _Region(False, at_narrowing=False), False, P)[1] == 2  # braking, lost sight
    assert next_way_out(backed, going, _Region(False, at_narrowing=True), False, P)[1] == 2
    assert next_way_out(backed, going, _Region(False, at_narrowing=False), False, P)[1] == 0
    assert next_way_out(backed, going, None, False, P)[1] == 0
