"""A contingency is released only when the driver's stopping path is disjoint from every track's region, the 1-D
line's object's too (:func:`ecu.core.planar.merged`): the rule, and the two catalogue cells it was made for."""

import pytest

from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import run_scenario
from cosim.matrix.catalogue import load_catalogue
from cosim.scenarios.loader import scenario_from_dict
from ecu.core.params import CoreParams
from ecu.core.plan import Plan
from ecu.core.planar import RegionCycle, merged
from ecu.core.region import decide
from ecu.core.region.objects import TrackBox
from ecu.core.region.paths import EgoState

P = CoreParams()
PEDESTRIAN = 1


def _released_plan() -> Plan:
    return Plan(proximity=1.0, throttle_limit_pct=0.0, decel_request_mps2=0.0, tightening_restricts=False,
                stopping_distance_m=15.0, disjoint=True, released=True)


def _region(walker_x_m: float) -> RegionCycle:
    """The region with one walker crossing toward our path ``walker_x_m`` ahead, 1.5 m to the right."""
    ego = EgoState(speed_mps=14.0, accel_mps2=0.0, decel_mps2=8.1)
    walker = TrackBox(walker_x_m, -1.5, -14.0, 1.4, PEDESTRIAN, P.track_position_sigma_m)
    return RegionCycle(ego, decide(ego, [walker], None, P.region), True, 0.0)


def test_no_release_while_the_lines_object_region_reaches_the_drivers_path():
    near = _region(12.0)
    assert not near.decision.driver_disjoint  # the walker's region (its response time) reaches our stop
    assert near.off_axis_disjoint  # the line judges it: before the rule, the line alone decided the release
    plan = merged(_released_plan(), near, False, P)
    assert not plan.released
    assert plan.disjoint  # invoking is unchanged: only the release waits


def test_release_when_every_region_is_disjoint():
    far = _region(80.0)
    assert far.decision.driver_disjoint
    assert merged(_released_plan(), far, False, P).released


def _run(catalogue: str, cell_id: str, strategy: str):
    cell = next(c for c in load_catalogue(catalogue).cells if c.cell_id == cell_id)
    sc = scenario_from_dict(cell.scenario_dict(0, 1))
    return run_scenario(sc, resolve_fmu(sc), strategy).metrics


@pytest.mark.parametrize("catalogue, cell_id, strategy", [
    # a child crossing at 5 km/h, judged standing by the line: released at 5.11 s on a speed estimate 0.9 m/s
    # low, re-invoked at 5.30 s, hit at 10.8 km/h (orange) before the rule
    ("ncap_vru", "CPNCO-25-60", "none"),
    # the lead car cuts out and reveals a stopped car: released for the 0.1 s the line confirms the new object,
    # hit at 24.3 km/h before the rule
    ("emergency_steering", "cut-out-free-90", "tightening"),
])
def test_cells_the_early_release_lost_no_longer_collide(catalogue, cell_id, strategy):
    metrics = _run(catalogue, cell_id, strategy)
    assert not metrics.collided, metrics.impact_speed_mps
