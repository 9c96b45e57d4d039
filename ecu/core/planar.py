"""The stopping region in the ECU's cycle (issue 22): what the plane adds to the 1-D decision.

The 1-D core (:mod:`ecu.core.plan`) judges the one ``ObjectTrack`` on its line, as before. With
planar tracks in the inputs (``RadarTrack`` slots; none: this module does nothing), each cycle:

1. **Ego**: the speed estimate, the command the 1-D plan bounds (``min(a_drv, a_hi)``), the
   model deceleration D, ``EscDynamics``'s yaw rate and the driver's road-wheel angle
   (``SteeringWheelAngle / steering_ratio``).
2. **Tracks** (:class:`can_dbc.planar.Track`) become :class:`~ecu.core.region.TrackBox` es with
   ``track_position_sigma_m``, but a track behind us, or beside us and not closing (:func:`ahead_or_beside`:
   only the rear corner radars' ``CornerTrack`` slots report any), is left to its own driver.
3. **Road**: the contract carries no lanes, so the ECU assumes its own (``lane_width_m``, centred
   on the ego, following its current curvature) and ``free_lanes_left`` / ``free_lanes_right``
   beside it (:func:`assumed_road`); a steering path stays within them and out of any holding a
   track's centre (UN R79 ESF, :mod:`ecu.core.region.road`); a standing track's box stands along it
   (:func:`ecu.core.region.objects.standing_heading_rad`).
4. **Decision** over every track (:func:`ecu.core.region.decide`), steering rows only with
   ``steering_authority``: reported in ``EcuRegionStatus`` and, in a contingency, the steering
   path (:mod:`ecu.core.steering`).
5. **What it adds to braking**: the driver's stopping path must also be disjoint from every track
   the line does not judge (:func:`line_track`: the 1-D object, when it is relevant, is the line's).
   Only when the decision over every track is not disjoint is that second check run (a subset of
   disjoint objects is disjoint), on the per-object gaps the decision already holds
   (:func:`ecu.core.region.decision.driver_disjoint_without`).
6. **What it adds to a release**: a contingency is released only when the driver's stopping path is disjoint
   from every track's region, the line's object's too (Prop. 1 over all agents). The line judges its object as
   standing when its speed along our line is low, so a child crossing at 5 km/h was released from while its
   region (its response time, :data:`ecu.core.region.params.CAPABILITIES`) still reached our path, and on a
   speed estimate that read 0.9 m/s low under full braking the line's own check passed by 0.15 m
   (``ncap_vru`` CPNCO-25-60 under ``none``: released at 5.11 s, re-invoked at 5.30 s, hit at 10.8 km/h;
   with this rule, no contact).

So a run whose only track is the 1-D object in our path is invoked by the 1-D core alone; an
object off the path, standing, cannot touch the straight stopping path of a car whose wheel is
straight (its nearest point is more than ``vehicle_width_m / 2 + path_margin_m`` = 1.91 m off the
axis, the footprint's half width is 1.01 m, the inflation 3 sigma = 0.51 m); a moving one off the
path adds a contingency when its own stopping region reaches the driver's stopping path.
The region's proximity is reported, not used: the throttle bound stays the 1-D strategy's (a car
in the next lane would otherwise bound the throttle).
"""

from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numpy as np

from can_dbc.planar import Track

from .intent import driver_accel_mps2
from .params import CoreParams
from .plan import Plan
from .relevance import nearest_track
from .region import EgoState, RegionDecision, Road, TrackBox, decide
from .region.crossing import LANE_CHANGE_WAY_OUTS, VEHICLE_CLASSES, crossing_proximity
from .region.lane_change import LaneChange, lane_change_mask, vehicle_mask
from .region.decision import driver_disjoint_without
from .region.narrowing import NARROWING_RULES, Turn
from .region.paths import current_curvature
from .types import CoreInputs, RegionReport


class RegionCycle(NamedTuple):
    """One cycle's region: the ego as the region saw it, the decision over every track, whether the
    driver's stopping path is disjoint from the tracks the 1-D line does not judge, and the nominal path's
    proximity to crossing vehicles (:mod:`ecu.core.region.crossing`) or, yielding at a narrowing, to the line
    where it waits (:mod:`ecu.core.region.narrowing`), whichever is higher."""

    ego: EgoState
    decision: RegionDecision
    off_axis_disjoint: bool
    crossing_proximity: float
    #: waiting in a standoff at a narrowing (:func:`ecu.core.region.narrowing.standoff`)
    standoff: bool = False
    #: taking (or having given back) its turn, it meets a vehicle on the move toward the narrowing
    contested: bool = False
    #: a narrowing lies ahead (:func:`ecu.core.region.narrowing.find_narrowing`)
    at_narrowing: bool = False


def ego_state(speed_mps: float, inputs: CoreInputs, plan: Plan, decel_mps2: float, params: CoreParams) -> EgoState:
    """Step 1 of the module docstring."""
    bound = params.strategy_rules.tighten(plan.proximity, params).accel_upper_mps2
    command = min(driver_accel_mps2(inputs.accel_pedal, inputs.brake_pedal, params), bound)
    return EgoState(speed_mps, command, decel_mps2, inputs.yaw_rate_radps,
                    inputs.steering_wheel_rad / params.steering_ratio)


def track_boxes(tracks: Sequence[Track], sigma_m: float) -> list[TrackBox]:
    """The contract's tracks as the region's boxes (nearest point, relative velocity, class, sigma)."""
    return [TrackBox(t.x_m, t.y_m, t.vx_mps, t.vy_mps, t.size_class, sigma_m) for t in tracks]


def ahead_or_beside(tracks: tuple[Track, ...], speed_mps: float, params: CoreParams) -> tuple[Track, ...]:
    """The tracks the region judges: all but those whose nearest point is behind our front bumper by more than the
    inflation ``sigma_factor * track_position_sigma_m`` (only the rear corner radars' ``CornerTrack`` slots report
    such; a forward track is ahead, x >= 0 but for its noise) and that are

    * a **follower**: moving, and behind our rear bumper (beyond ``length_m`` and the inflation). It cannot reach
      our stopping path unless it follows us, and a follower is its own driver's to avoid (StVO section 4(1): the
      distance to the vehicle ahead must as a rule let the follower stop behind it when it brakes suddenly): its
      stopping region covers ours at any usual following distance (at 50 km/h a car's region reaches 24 m ahead
      of it), so judging it would brake the lead for the car behind it;
    * **beside** us (its nearest point beyond our side, ``|y| >= width_m / 2``) and not closing on our side
      (``y v_y >= 0``, standing included): our stopping path runs forward, away from it, while its inflated box
      may touch our footprint and hold us at a stop (two cars stopped side by side would both wait for ever).

    A track on us (x < 0 within our width) stays: it is a contact, not a car beside us."""
    region = params.region
    sigma_m = region.sigma_factor * params.track_position_sigma_m
    if all(t.x_m >= -sigma_m for t in tracks):
        return tracks
    rear_m, side_m = -region.length_m - sigma_m, 0.5 * region.width_m

    def left_out(t: Track) -> bool:
        moving = math.hypot(t.vx_mps + speed_mps, t.vy_mps) > region.moving_object_speed_mps
        beside = abs(t.y_m) >= side_m and not (moving and t.y_m * t.vy_mps < 0.0)
        return t.x_m < -sigma_m and ((moving and t.x_m < rear_m) or beside)

    return tuple(t for t in tracks if not left_out(t))


def assumed_road(ego: EgoState, params: CoreParams) -> Road:
    """Our lane centred on the ego and the free lanes beside it, along the current curvature (step 3)."""
    w = params.lane_width_m
    right = -0.5 * w - params.free_lanes_right * w
    count = 1 + params.free_lanes_left + params.free_lanes_right
    return Road(tuple(right + k * w for k in range(count + 1)), 0.0, current_curvature(ego, params.region))


def line_track(tracks: Sequence[Track], inputs: CoreInputs, in_our_path: bool, speed_mps: float,
               params: CoreParams) -> int | None:
    """The index of the track that is the 1-D core's object (:func:`ecu.core.relevance.nearest_track`); None when
    that object is not ``in_our_path`` (valid and in the predicted path, :mod:`ecu.core.relevance`), no track
    is near it, or it is an oncoming vehicle (:func:`oncoming`). Confirmed or not, it is left to the line: while
    the line confirms a new object (3 reports), the line does not invoke for it (judging it in the region then
    changed the steering contingency's timing, and the late stationary car at 80 km/h was hit, so it is not
    done); a contingency already invoked is not released for it, since a release needs every track's region
    disjoint (:func:`merged`: a car that cuts out and reveals a stopped one no longer ends the braking for
    those 0.1 s, ``emergency_steering`` cut-out-free-90 and cut-out-occupied-90)."""
    i = nearest_track(tracks, inputs, params) if in_our_path else None
    return None if i is not None and oncoming(tracks[i], speed_mps, params) else i


def oncoming(track: Track, speed_mps: float, params: CoreParams) -> bool:
    """A vehicle coming toward us over ground (its speed along our heading below ``-moving_object_speed_mps``
    of the region): the line stops short of where it is now, as if it stood (its stopping region is its own
    responsibility, :mod:`ecu.core.stopping_path`), which two equipped cars head-on both do, and each then
    covers its own stop toward the other: they meet (issue 23, ``crd fleet narrow_passage``). The region
    judges such a track by its stopping region, and the driver's stopping path is kept disjoint from it too."""
    return track.size_class in VEHICLE_CLASSES and track.vx_mps + speed_mps < -params.region.moving_object_speed_mps


def region_cycle(speed_mps: float, inputs: CoreInputs, plan: Plan, decel_mps2: float, params: CoreParams,
                 in_our_path: bool, turn: Turn = Turn.NONE) -> RegionCycle | None:
    """Steps 1-5 of the module docstring; None without planar tracks. ``in_our_path``: the line judges the 1-D
    object (:func:`line_track`); ``turn``: where the car stands in the way-out patience (:mod:`ecu.core.way_out`):
    taking its turn, no tightening against crossing vehicles nor for a standoff at a narrowing."""
    tracks = ahead_or_beside(inputs.tracks, speed_mps, params)
    if not tracks:
        return None
    ego = ego_state(speed_mps, inputs, plan, decel_mps2, params)
    boxes = track_boxes(tracks, params.track_position_sigma_m)
    road = assumed_road(ego, params)
    decision = decide(ego, boxes, road, params.region, steer=params.steering_authority)
    off_axis = True
    if not decision.driver_disjoint and plan.disjoint:
        off_axis = driver_disjoint_without(decision, line_track(tracks, inputs, in_our_path, speed_mps, params))
    narrowing = NARROWING_RULES[params.way_out](boxes, ego, params, turn)
    crossing = 0.0 if turn == Turn.TAKING else crossing_proximity(
        decision, boxes, speed_mps, params.region, params.way_out,
        0.0 if params.way_out == "none" else params.way_out_path_m, lane_change(decision, boxes, ego, params))
    return RegionCycle(ego, decision, off_axis, max(crossing, narrowing.proximity), narrowing.standoff,
                       narrowing.contested, narrowing.found)


def held_back(region: RegionCycle | None) -> bool:
    """What the way-out patience counts (:mod:`ecu.core.way_out`): something near the nominal path (the region's
    proximity), or a standoff at a narrowing (waiting 20 m before it, nothing need be near)."""
    return region is not None and (region.decision.proximity > 0.0 or region.standoff)


def lane_change(decision: RegionDecision, boxes: Sequence[TrackBox], ego: EgoState,
                params: CoreParams) -> np.ndarray | None:
    """The vehicles of the lane our path moves into (:mod:`ecu.core.region.lane_change`), under the way-out rules
    that give way to them (``LANE_CHANGE_WAY_OUTS``); None under the others."""
    if params.way_out not in LANE_CHANGE_WAY_OUTS or decision.objects.centre.size == 0:
        return None
    ours = LaneChange(current_curvature(ego, params.region), params.region.width_m, params.lane_width_m,
                      params.way_out_path_m)
    return lane_change_mask(decision.objects, vehicle_mask([b.size_class for b in boxes], VEHICLE_CLASSES),
                            np.array([b.y_m for b in boxes]), ours)


def tightened(plan: Plan, proximity: float, params: CoreParams) -> Plan:
    """The plan with the strategy's bound at ``proximity`` too, when that is higher than the plan's: the more
    restrictive of the two bounds (``none`` and ``conservative`` do not tighten: the plan as it is)."""
    if proximity <= plan.proximity:
        return plan
    bound = params.strategy_rules.tighten(proximity, params)
    if not bound.restricts:
        return plan
    return plan._replace(proximity=proximity, throttle_limit_pct=min(plan.throttle_limit_pct, bound.throttle_limit_pct),
                         decel_request_mps2=max(plan.decel_request_mps2, bound.decel_request_mps2),
                         tightening_restricts=True)


def merged(plan: Plan, region: RegionCycle | None, steering_held: bool, params: CoreParams) -> Plan:
    """The 1-D plan with the region's addition: tightened toward crossing vehicles (:func:`tightened`); not
    disjoint (nor released) while an off-axis object's region reaches the driver's stopping path, or while a
    steering contingency is held (``steering_held``: it brakes to a stop along its path,
    :mod:`ecu.core.steering`)."""
    if region is not None:
        plan = tightened(plan, region.crossing_proximity, params)
    if not steering_held and (region is None or region.off_axis_disjoint):
        if region is not None and plan.released and not region.decision.driver_disjoint:
            return plan._replace(released=False)  # a release: disjoint from every region, the line's object's too
        return plan
    return plan._replace(disjoint=False, released=False)


def report(region: RegionCycle | None) -> RegionReport | None:
    """``EcuRegionStatus``'s values of the decision (None: not evaluated)."""
    if region is None:
        return None
    d = region.decision
    return RegionReport(int(d.kind), d.proximity, d.curvature_1pm, d.clearance_m, d.stopping_distance_m)
