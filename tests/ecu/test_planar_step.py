"""The stopping region wired into the core step (issue 22): planar tracks reach the region, a 1-D standing
target's run is decided as without them, an off-axis object's region adds a contingency, the contingency
rules through the whole step, the steering request with and without steering authority, and
EcuRegionStatus on the bus."""

import dataclasses
import math

import pytest

from can_dbc import check_alone
from can_dbc.contract import enumeration
from can_dbc.planar import Track
from ecu import EcuConfig
from ecu.bus_port import InputLatch, region_message
from ecu.core import CoreInputs, CoreState, Mode, step
from ecu.core.region import Contingency
from ecu.core.types import CoreOutputs, RegionReport

P = EcuConfig(strategy="tightening")
STEER = dataclasses.replace(P, equipment="planar_steering")  # steering authority: the equipment that steers
UNKNOWN, CAR, PEDESTRIAN = 0, 4, 1
CYCLE_S = 0.01


def inputs(t_s, speed_mps=25.0, range_m=None, lateral_m=0.0, tracks=(), yaw_rate=0.0, accel=0.3):
    """Fresh inputs at ``t_s``: the ObjectTrack of an in-path object at ``range_m`` (None: none), and ``tracks``."""
    return CoreInputs(t_s=t_s, wheel_speeds_mps=(speed_mps,) * 4, accel_pedal=accel, object_valid=range_m is not None,
                      object_range_m=range_m or 0.0, object_range_rate_mps=-speed_mps if range_m else 0.0,
                      object_lateral_m=lateral_m, wheel_rx_t_s=t_s, driver_rx_t_s=t_s, object_rx_t_s=t_s,
                      tracks=tuple(tracks), yaw_rate_radps=yaw_rate)


def line_track(range_m, lateral_m=0.0, speed_mps=25.0):
    """The 1-D object as today's master sends it in the RadarTrack slots (cosim.loop.planar_frames.tracks_of)."""
    return Track(0, UNKNOWN, 7, range_m, lateral_m, -speed_mps, 0.0)


def drive(frames, params=P, speed_mps=25.0):
    """Run ``frames(k) -> dict of inputs() keywords`` from a settled state; the (state, outputs) of every cycle."""
    state, out = CoreState(), []
    for k in range(20):  # settle: leave FAULT, initialise the speed estimate
        state, _ = step(state, inputs(k * CYCLE_S, speed_mps), params)
    for k in range(20, 20 + 200):
        state, o = step(state, inputs(k * CYCLE_S, speed_mps, **frames(k)), params)
        out.append((state, o))
    return out


# -- the 1-D standing target: the tracks change nothing ---------------------------------------------------------
@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening", "adaptive"])
@pytest.mark.parametrize("lateral_m", [0.0, 0.8, 1.5, 2.5, -3.5])
def test_a_standing_target_on_the_line_is_decided_as_without_tracks(strategy, lateral_m):
    params = dataclasses.replace(P, strategy=strategy)
    gap0 = 70.0

    def with_tracks(k):
        r = gap0 - 25.0 * (k - 20) * CYCLE_S
        return {"range_m": r, "lateral_m": lateral_m, "tracks": [line_track(r, lateral_m)]}

    def without(k):
        return {key: v for key, v in with_tracks(k).items() if key != "tracks"}

    planar, line = drive(with_tracks, params), drive(without, params)
    assert any(o.mode is Mode.CONTINGENCY for _, o in line) == (abs(lateral_m) < 1.9)
    for (_, a), (_, b) in zip(planar, line):
        assert a._replace(region=None) == b
        assert a.region is not None and not a.steer_active


# -- what the region adds -------------------------------------------------------------------------------------
def test_an_off_axis_object_whose_region_reaches_our_path_starts_a_contingency():
    """A car crossing from the right at 10 m/s, 30 m ahead and 6 m to the side: the line sees nothing (no
    ObjectTrack), its stopping region (12.5 m along its velocity) reaches our stopping path."""
    crossing = {"tracks": [Track(3, CAR, 7, 30.0, -6.0, -25.0, 10.0)]}
    planar = drive(lambda k: crossing)
    line = drive(lambda k: {})
    assert planar[0][1].mode is Mode.CONTINGENCY and planar[0][1].brake_decel_request_mps2 == P.contingency_decel_mps2
    assert planar[0][1].region.contingency == Contingency.LEAST_IMPACT
    assert all(o.mode is Mode.STANDBY for _, o in line)


def test_a_car_in_the_next_lane_at_our_speed_adds_nothing():
    beside = {"tracks": [Track(4, CAR, 7, 20.0, 2.65, 0.0, 0.0)]}
    assert all(o.mode is Mode.STANDBY and o.region.contingency == Contingency.DRIVER_PATH for _, o in drive(lambda k: beside))


# -- the contingency rules through the whole step ---------------------------------------------------------------
def _standing_car(gap0):
    def frames(k):
        r = gap0 - 25.0 * (k - 20) * CYCLE_S
        return {"range_m": r, "tracks": [Track(1, CAR, 7, r, -0.85, -25.0, 0.0)]}
    return frames


def test_rule_1_driver_path_far_from_everything():
    (_, o), *_ = drive(_standing_car(150.0), STEER)
    assert o.region.contingency == Contingency.DRIVER_PATH and o.mode is Mode.STANDBY and not o.steer_active


def test_rule_3_steer_and_brake_with_authority_and_its_request_ramps_left():
    run = drive(_standing_car(45.0), STEER)
    kinds = [o.region.contingency for _, o in run]
    first = next(i for i, (_, o) in enumerate(run) if o.steer_active)
    assert Contingency.STEER_AND_BRAKE in kinds[:first + 1]
    requests = [o.steer_request_rad for _, o in run[first:first + 30]]
    steps = [b - a for a, b in zip([0.0, *requests], requests)]
    assert all(0.0 < s <= 0.4 * CYCLE_S + 1e-12 for s in steps[:5])  # left, at most the rate limit a cycle
    assert all(0.0 <= s <= 0.4 * CYCLE_S + 1e-12 for s in steps) and requests[-1] > 5 * 0.4 * CYCLE_S
    _, o = run[first]
    assert o.mode is Mode.CONTINGENCY and 0.0 < o.brake_decel_request_mps2 < P.contingency_decel_mps2
    assert all(o.mode is Mode.CONTINGENCY for _, o in run[first:150])  # held along its path (the range stays > 0)


def test_without_authority_the_same_scene_brakes_in_lane_and_never_steers():
    run = drive(_standing_car(45.0), P)
    assert not any(o.steer_active for _, o in run)
    assert {o.region.contingency for _, o in run} <= {Contingency.DRIVER_PATH, Contingency.LEAST_IMPACT}
    assert any(o.brake_decel_request_mps2 == P.contingency_decel_mps2 for _, o in run)


def test_rule_4_least_impact_when_no_path_is_disjoint():
    """A car 12 m ahead at 25 m/s: nothing stops short of it, steering or not."""
    run = drive(_standing_car(12.0), STEER)
    assert run[0][1].region.contingency == Contingency.LEAST_IMPACT
    assert any(o.mode is Mode.CONTINGENCY for _, o in run[:10])  # once the line has confirmed its track


def test_rule_2_brake_in_lane_needs_a_lane_the_ecu_cannot_see():
    """The ECU's assumed lane follows its current curvature, so braking in lane is the driver's own path: rule 2
    cannot differ from rule 1 until lanes are perceived (ecu.core.planar, step 3)."""
    seen = {o.region.contingency for gap in (12.0, 30.0, 45.0, 150.0) for _, o in drive(_standing_car(gap), STEER)}
    assert Contingency.BRAKE_IN_LANE not in seen


# -- the status frame and the latch -----------------------------------------------------------------------------
def test_contingency_enumeration_is_the_dbcs():
    dbc = {int(v): str(n) for v, n in enumeration("EcuRegionStatus", "Contingency").items()}
    assert {c.value: c.name for c in Contingency} == {v: n for v, n in dbc.items() if n != "NOT_EVALUATED"}


def _outputs(region):
    return CoreOutputs(Mode.STANDBY, False, 100.0, 0.0, 0, 0.0, 0.0, 0.0, True, False, region=region)


def test_region_status_encodes_decodes_and_saturates():
    sig = check_alone(region_message(_outputs(RegionReport(2, 0.37, -0.0123, math.inf, 48.25)), 3)).signals
    assert sig["Contingency"] == 2 and sig["RegionProximity"] == pytest.approx(0.37)
    assert sig["RegionCurvature"] == pytest.approx(-0.0124, abs=1e-4)  # 0.0002 1/m steps
    assert sig["RegionClearance"] == pytest.approx(25.55) and sig["RegionStoppingDistance"] == pytest.approx(48.2)
    none = check_alone(region_message(_outputs(None), 4)).signals
    assert none["Contingency"] == 4 and none["RegionStoppingDistance"] == 0.0


def test_latch_gives_the_tracks_until_they_time_out():
    from can_dbc import encode
    from can_dbc.planar import TRACK_SLOTS, track_signals
    from can_dbc.receiver import Receiver

    latch, rx = InputLatch(), Receiver(names=list(TRACK_SLOTS))
    tr = Track(5, CAR, 7, 20.0, 1.0, -3.0, 0.5)
    for name, slot in TRACK_SLOTS.items():
        latch.ingest(rx.receive(encode(name, track_signals(tr if slot == 2 else None, slot), 0), 0.0), 0.0)
    assert latch.live_tracks(0.1, 0.25) == (tr,)
    assert latch.live_tracks(0.3, 0.25) == ()
