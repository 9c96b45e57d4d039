"""The reacting driver (cosim/world/driver_models.py): lifts off a reaction time after he feels the car brake by
itself, presses again a reaction time after it stops; reaction times drawn from Green (2000)'s range, seeded."""

import pytest

from cosim.errors import ConfigError
from cosim.scenarios.config import DriverConfig
from cosim.scenarios.loader import scenario_from_dict
from cosim.world.driver_models import make_driver

CFG = DriverConfig(model="reacting")
DT = 0.01


def _drive(model, speeds):
    """(time, accel %) per ECU cycle for a speed trace, one sample a cycle."""
    return [(round(k * DT, 2), model(k * DT, 0.0, v).accel_pct) for k, v in enumerate(speeds)]


def _changes(trace):
    return [(t, a) for (t, a), (_, before) in zip(trace[1:], trace) if a != before]


#: 2 s cruising at 20 m/s, 1 s braking at 5 m/s^2 (felt: above 1.5), then 4 s steady at 15 m/s
SPEEDS = [20.0] * 200 + [20.0 - 0.05 * k for k in range(1, 101)] + [15.0] * 400


def test_he_lifts_off_a_reaction_time_after_the_braking_begins_and_presses_a_reaction_time_after_it_ends():
    (lift_t, lift), (press_t, press) = _changes(_drive(make_driver(CFG, 1), SPEEDS))
    assert lift == 0.0 and press == 100.0
    assert 2.01 + CFG.reaction_time_min_s - DT <= lift_t <= 2.01 + CFG.reaction_time_max_s + DT
    assert 3.0 + CFG.reaction_time_min_s - DT <= press_t <= 3.0 + CFG.reaction_time_max_s + DT


def test_the_reaction_times_are_seeded():
    assert _changes(_drive(make_driver(CFG, 1), SPEEDS)) == _changes(_drive(make_driver(CFG, 1), SPEEDS))
    assert _changes(_drive(make_driver(CFG, 1), SPEEDS)) != _changes(_drive(make_driver(CFG, 2), SPEEDS))


def test_lifted_he_waits_while_the_car_brakes_again():
    # braking from 2.0 to 3.0 s, steady 0.3 s (a press falls due 0.7 s after 3.0 s), braking again from 3.3 to 5.3 s
    speeds = SPEEDS[:300] + [15.0] * 30 + [15.0 - 0.05 * k for k in range(1, 201)] + [5.0] * 300
    cfg = DriverConfig(model="reacting", reaction_time_min_s=0.7, reaction_time_max_s=0.7)
    assert _changes(_drive(make_driver(cfg, 3), speeds)) == [(2.7, 0.0), (6.0, 100.0)]


def test_a_shortest_reaction_time_above_the_longest_is_refused_naming_the_key():
    with pytest.raises(ConfigError, match=r"^driver\.reaction_time_min_s: expected at most"):
        scenario_from_dict({"driver": {"model": "reacting", "reaction_time_min_s": 2.0, "reaction_time_max_s": 1.0}})
