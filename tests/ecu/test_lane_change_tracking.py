"""Holding a lane change on its S: the planned pose, the tracking law, the dead reckoning and the latch."""

import math

import numpy as np
import pytest

from can_dbc.contract import enumeration
from ecu.core import CoreParams, CoreState, Mode
from ecu.core.lane_change_tracking import (
    TRACKING_TIME_S, advanced, half_length_m, planned_pose, tracking_curvature)
from ecu.core.planar import RegionCycle
from ecu.core.region import EgoState, Road, TrackBox, decide, region_params
from ecu.core.steering import latched_curvature, steering
from ecu.core.types import Evasion

CLASS = {name: value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()}
PARAMS = CoreParams(steering_authority=True)
RP = region_params(PARAMS)
D = PARAMS.model_decel_mps2
TWO_LANES = Road((-1.75, 1.75, 5.25))  # our lane and a free lane on the left


@pytest.mark.parametrize("kappa, offset", [(0.01, 3.5), (-0.01, -3.5), (0.005, 4.24), (0.03, 3.87)])
def test_the_planned_s_ends_the_offset_over_and_parallel(kappa, offset):
    half = half_length_m(kappa, offset)
    assert 2.0 * (1.0 - math.cos(abs(kappa) * half)) / abs(kappa) == pytest.approx(abs(offset))
    assert planned_pose(kappa, offset, 0.0) == (kappa, 0.0, 0.0)
    k_mid, y_mid, psi_mid = planned_pose(kappa, offset, half)
    assert k_mid == pytest.approx(-kappa) and y_mid == pytest.approx(offset / 2) and psi_mid == pytest.approx(kappa * half)
    for s in (2.0 * half - 1e-6, 2.0 * half, 5.0 * half):  # continuous into the straight in the new lane
        _, y, psi = planned_pose(kappa, offset, s)
        assert y == pytest.approx(offset, abs=1e-5) and psi == pytest.approx(0.0, abs=1e-5)
    assert planned_pose(kappa, offset, 3.0 * half)[0] == 0.0


def test_the_planned_s_matches_integrating_its_curvature():
    kappa, offset, ds = 0.012, 3.87, 0.001
    y = psi = 0.0
    s = 0.0
    while s < 2.5 * half_length_m(kappa, offset):
        k, _, _ = planned_pose(kappa, offset, s + 0.5 * ds)
        y += ds * math.sin(psi + 0.5 * k * ds)
        psi += k * ds
        s += ds
        _, y_p, psi_p = planned_pose(kappa, offset, s)
        assert y == pytest.approx(y_p, abs=2e-3) and psi == pytest.approx(psi_p, abs=1e-4)


def test_on_its_plan_the_car_is_asked_for_the_plans_curvature_and_errors_steer_back():
    kappa, lead = 0.01, 8.0
    on_plan = Evasion(3.5, lead, 20.0, *reversed(planned_pose(kappa, 3.5, 20.0 - lead)[1:]))
    assert tracking_curvature(kappa, on_plan, 25.0) == pytest.approx(planned_pose(kappa, 3.5, 20.0)[0])
    left = on_plan._replace(lateral_m=on_plan.lateral_m + 0.5)
    turned_left = on_plan._replace(heading_rad=on_plan.heading_rad + 0.05)
    d = 25.0 * TRACKING_TIME_S
    assert tracking_curvature(kappa, left, 25.0) == pytest.approx(tracking_curvature(kappa, on_plan, 25.0) - 0.5 / d ** 2)
    assert tracking_curvature(kappa, turned_left, 25.0) == pytest.approx(
        tracking_curvature(kappa, on_plan, 25.0) - 2 * 0.05 / d)
    assert tracking_curvature(kappa, Evasion(), 25.0) == kappa  # an arc keeps its own curvature


def test_dead_reckoning_follows_a_circle():
    v, r, dt = 20.0, 0.2, 0.01
    e = Evasion(3.5)
    for _ in range(100):
        e = advanced(e, v, r, dt)
    radius = v / r
    assert e.travel_m == pytest.approx(20.0) and e.heading_rad == pytest.approx(0.2)
    assert e.lateral_m == pytest.approx(radius * (1.0 - math.cos(0.2)), rel=1e-4)
    assert advanced(Evasion(), v, r, dt) == Evasion()  # an arc's is not reckoned


def _drive(v, kappa, offset, lead, start, lag_s=0.27, seconds=6.0, dt=0.01):
    """A kinematic car whose curvature follows the command through a first-order lag (the plant's steering),
    started ``start`` (lateral m, heading rad) off the plan; the largest lateral error after the S and the end."""
    e = Evasion(offset, lead, 0.0, start[1], start[0])
    k_car, worst, t = 0.0, 0.0, 0.0
    end_s = lead + 2.0 * half_length_m(kappa, offset)
    while t < seconds:
        k_car += (tracking_curvature(kappa, e, v) - k_car) * dt / lag_s
        e = advanced(e, v, v * k_car, dt)
        if e.travel_m > end_s + v * 2 * TRACKING_TIME_S:
            worst = max(worst, abs(e.lateral_m - offset))
        t += dt
    return e, worst


@pytest.mark.parametrize("v", [22.0, 27.7, 33.3])
def test_with_the_steering_lag_the_car_settles_in_the_new_lane(v):
    kappa = 6.0 / v ** 2
    lead = v * (RP.hold_time_s + RP.steer_lag_s)
    e, worst = _drive(v, kappa, 3.87, lead, (0.0, 0.0))
    assert e.lateral_m == pytest.approx(3.87, abs=0.05) and abs(e.heading_rad) < 0.005
    assert worst < 0.25  # no swing into the next lane after the S


def test_an_initial_error_decays_without_overshoot():
    v = 25.0
    e = Evasion(3.5, 0.0, 1000.0, 0.0, 3.0)  # straight in the new lane, 0.5 m short of it
    lateral = []
    for _ in range(600):
        e = advanced(e, v, v * tracking_curvature(0.005, e, v), 0.01)
        lateral.append(e.lateral_m)
    assert max(lateral) <= 3.5 + 1e-6 and lateral[-1] == pytest.approx(3.5, abs=0.01)
    assert all(b >= a - 1e-9 for a, b in zip(lateral, lateral[1:]))  # critically damped: monotone


def _cycle(v, x):
    """The region's cycle for a car parked ``x`` ahead in our lane, the left lane free."""
    ego = EgoState(v, 0.0, D)
    return RegionCycle(ego, decide(ego, [TrackBox(x, 0.0, -v, 0.0, CLASS["CAR"], 0.05)], TWO_LANES, RP), True, 0.0)


def test_a_lane_change_among_standing_objects_latches_short_of_the_standoff_an_arc_only_beyond_the_range():
    lane_change, arc = _cycle(27.7, 41.0), _cycle(30.0, 58.0)
    assert lane_change.decision.evasion_offset_m > 0.0 and arc.decision.evasion_offset_m == 0.0
    state, mode = CoreState(), Mode.CONTINGENCY
    for shortfall, evades, arcs in ((-PARAMS.standoff_m - 0.1, False, False), (-1.0, True, False), (0.1, True, True)):
        assert (latched_curvature(state, mode, lane_change, shortfall, PARAMS) is not None) is evades
        assert (latched_curvature(state, mode, arc, shortfall, PARAMS) is not None) is arcs
    objects = lane_change.decision.objects
    moving = lane_change._replace(decision=lane_change.decision._replace(
        objects=objects._replace(moving=np.ones_like(objects.moving))))
    assert latched_curvature(state, mode, moving, -1.0, PARAMS) is None  # a moving object: no standoff margin
    assert latched_curvature(state, mode, moving, 0.1, PARAMS) is not None


def test_the_latched_lane_change_carries_its_s_and_steers_left_then_brakes_inside_the_friction_circle():
    cycle = _cycle(27.7, 41.0)
    first = steering(CoreState(), Mode.CONTINGENCY, cycle, 1.0, 0.0, 0.0, 27.7, D, PARAMS)
    assert first.evasion.offset_m == cycle.decision.evasion_offset_m and first.evasion.lead_m > 0.0
    assert first.evasion.travel_m == pytest.approx(27.7 * PARAMS.cycle_s) and first.request_rad > 0.0
    lateral = 27.7 ** 2 * tracking_curvature(first.curvature_1pm, Evasion(*first.evasion[:2]), 27.7)
    assert first.decel_mps2 == pytest.approx(math.sqrt(D * D - lateral * lateral))
    held = CoreState(mode=Mode.CONTINGENCY, steer_curvature_1pm=first.curvature_1pm, steer_evasion=first.evasion)
    spinning = steering(held, Mode.CONTINGENCY, None, 1.0, 0.0, 0.4, 27.7, D, PARAMS)  # 11 m/s^2 measured
    assert spinning.decel_mps2 == 0.0 and spinning.evasion.travel_m > first.evasion.travel_m
