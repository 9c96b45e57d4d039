"""Our extension ``adaptive`` on a wet road, the paper scenario otherwise unchanged (issue 14)."""

import dataclasses

import pytest

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import run_scenario
from cosim.scenarios.loader import load_scenario

pytestmark = pytest.mark.slow


def test_adaptive_stops_short_where_tightening_collides_at_mu_0_6():
    base = load_scenario(PAPER_SCENARIO)
    wet = dataclasses.replace(base, plant=dataclasses.replace(base.plant, road_friction=0.6))
    fmu = resolve_fmu(base)
    tight = run_scenario(wet, fmu, "tightening").metrics
    adaptive = run_scenario(wet, fmu, "adaptive").metrics
    assert tight.collided  # the paper's best strategy, with its dry peak, hits the cyclist
    assert not adaptive.collided and adaptive.final_gap_m > 2.0
