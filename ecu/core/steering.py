"""The steering contingency's request (issue 22, item 3): ``SteeringOverride``'s road-wheel angle overlay.

Only with ``steering_authority`` (the EPS applies our overlay); without it nothing is requested and
the region's decision has no steering rows (:func:`ecu.core.region.decide`, ``steer=False``).

* **Latch**: in ``CONTINGENCY``, the first cycle whose region decision is ``STEER_AND_BRAKE`` (a steering
  path whose stopping path is disjoint) while braking cannot keep the 1-D line's relevant object from
  contact (its stopping path, without the standoff, is longer than the range: :func:`shortfall` > 0) latches
  that path's curvature,
  clamped into the joint bounds tightened at the decision's proximity
  (:func:`ecu.core.region.tightened_bounds`; at proximity 1 the contingency's own). It is not
  re-decided: from a pose that already turns the assumed lane (:func:`ecu.core.planar.assumed_road`)
  would be re-centred on the ego, and the rows' curvatures ``a_j / v^2`` grow as the car slows (measured:
  re-deciding every cycle wound the curvature up and left the road).
  The contingency is the stop along that path: while a path is latched and the car moves, the
  plan is held not released (:func:`steering_held`, :func:`ecu.core.planar.merged`), so the mode
  stays ``CONTINGENCY`` to standstill. Any other mode (a fault) drops it.
  Without the second condition the ECU steered for a parked car on the outside of a curve that its
  line (a straight path) and its region (inflated 3 sigma, the box aligned with the ego) both
  misjudged (``curve_parked_car``: it left its lane). ``LEAST_IMPACT`` on a steering row is reported
  but not steered: its ranking assumes the others stop
  within their regions, and a crossing pedestrian who walks on was steered into (measured, ncap_vru: 41
  cells lost their band with it); the contingency then brakes in lane at full.
  A **lane change** (:mod:`ecu.core.region.evasion`, chosen only when no arc is disjoint) among standing
  objects only (none of the region's tracks moving) latches once braking cannot stop the standoff short of
  the line's object (``shortfall > -standoff``): the 1-D plan leaves out the radar's latency, and with the
  standoff-less test the car braked in lane into the parked car of late-stationary-free-80 (29.9 km/h) while
  the region's lane change was disjoint (measured: the plan's 28.5 m against a range of 30.6 m). With a
  moving object the test stays standoff-less: a crossing pedestrian walks on out of the lane, and with the
  standoff the car steered into the pedestrians of ncap_vru CPNA-50-60 and CPNCO-50-60 (conservative), where
  braking in lane had stopped short. The lane change is held on its planned S, closed loop
  (:mod:`ecu.core.lane_change_tracking`).
* **Target**: the overlay that makes the road-wheel angle ``atan(kappa L)`` on top of the driver's
  (``kappa`` an arc's, or a lane change's tracking curvature, :func:`ecu.core.lane_change_tracking.tracking_curvature`),
  corrected by the curvature the car actually follows (``kappa_m`` = yaw rate / speed above 1 m/s):
  ``atan(kappa L) + atan((kappa - kappa_m) L) - delta_driver``, within the DBC's range of
  ``SteerAngleRequest``; 0 unlatched. Without the correction the braking car oversteered into a spin
  (measured: yaw rate three times the commanded curvature's under full braking).
* **Rate**: the request moves toward the target by at most ``steer_rate_max_radps`` (0.4 rad/s,
  below the 23 deg/s ``SigMaxRate`` the EPS enforces) per second of cycle, back to 0 the same way;
  ``SteerActive`` while a path is latched or the request is not yet back at 0.
* **Braking** while steering: what the friction circle leaves, ``min(C, sqrt(A^2 - (v^2 kappa)^2))``,
  ``A`` the model deceleration D (:func:`ecu.core.region.decision.contingency_decel_mps2`'s rule). For a lane
  change the lateral acceleration is the larger of ``v^2 kappa`` and the measured ``v r``: while the tracking
  turns the car more than its plan the brakes leave it the grip (the plant spins when it brakes hard in a turn
  from about 0.35 g, fmu_plant/README.md, Known limits), and it brakes along the S too, where the open-loop
  version coasted (the S is the same path by distance, so its stop is a part of the planned one).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from can_dbc.contract import signal_range
from can_dbc.units import dbc_per_si

from .lane_change_tracking import advanced, tracking_curvature
from .params import CoreParams
from .plan import Plan
from .planar import RegionCycle
from .region import Contingency, tightened_bounds
from .types import CoreState, Evasion, Mode

_CONTINGENCY = Mode["CONTINGENCY"]

_DEG_PER_RAD = dbc_per_si("deg")
#: the DBC's range of SteerAngleRequest (rad)
_REQUEST_LOW_DEG, _REQUEST_HIGH_DEG = signal_range("SteeringOverride", "SteerAngleRequest")
REQUEST_RANGE_RAD = (_REQUEST_LOW_DEG / _DEG_PER_RAD, _REQUEST_HIGH_DEG / _DEG_PER_RAD)


class Steering(NamedTuple):
    """The cycle's steering: the latched curvature (None: none), the overlay request (rad), SteerActive, the
    deceleration the friction circle leaves beside the turn (inf: no limit), and the held lane change."""

    curvature_1pm: float | None
    request_rad: float
    active: bool
    decel_mps2: float
    evasion: Evasion = Evasion()


NO_STEERING = Steering(None, 0.0, False, math.inf)


def latched(state: CoreState, mode: Mode, region: RegionCycle | None, shortfall_m: float,
            params: CoreParams) -> tuple[float | None, Evasion]:
    """The held path: its curvature (None: none) and, for a lane change, its S (module docstring, Latch)."""
    kappa = latched_curvature(state, mode, region, shortfall_m, params)
    if kappa is None:
        return None, Evasion()
    if state.steer_curvature_1pm is None and region is not None:
        return kappa, Evasion(region.decision.evasion_offset_m, region.decision.evasion_lead_m)
    return kappa, state.steer_evasion


def _braking_mps2(kappa_1pm: float, evasion: Evasion, speed_mps: float, yaw_rate_radps: float,
                  decel_mps2: float) -> float:
    """What the friction circle leaves beside the turn (module docstring, Braking): for a lane change the larger of
    the commanded and the measured lateral acceleration (its tracking turns the car by more than the plan)."""
    lateral = speed_mps * speed_mps * abs(kappa_1pm)
    if evasion.offset_m != 0.0:
        lateral = max(lateral, abs(speed_mps * yaw_rate_radps))
    return math.sqrt(max(0.0, decel_mps2 * decel_mps2 - lateral * lateral))


def latched_curvature(state: CoreState, mode: Mode, region: RegionCycle | None, shortfall_m: float,
                      params: CoreParams) -> float | None:
    """The held steering path's curvature (module docstring, Latch); None for none."""
    if mode is not _CONTINGENCY:
        return None
    held: float | None = state.steer_curvature_1pm
    if held is not None or region is None or region.decision.kind is not Contingency.STEER_AND_BRAKE:
        return held
    if shortfall_m <= -_latch_margin_m(region, params):
        return None
    bounds = tightened_bounds(region.ego, region.decision, params.region)
    return min(bounds.curvature_hi_1pm, max(bounds.curvature_lo_1pm, region.decision.curvature_1pm))


def _latch_margin_m(region: RegionCycle, params: CoreParams) -> float:
    """How far short of the range braking may still stop for the decision to latch (module docstring, Latch): the
    standoff for a lane change among standing objects only, else 0."""
    standing = not bool(region.decision.objects.moving.any())
    return params.standoff_m if region.decision.evasion_offset_m != 0.0 and standing else 0.0


def shortfall(relevant: bool, plan: Plan, range_m: float) -> float:
    """How far (m) braking falls short of the line's relevant object: the plan's stopping path (to standstill, or to
    zero relative speed behind a moving object) less the range; -inf without a relevant object. Positive: braking
    cannot keep it from contact (module docstring, Latch)."""
    return plan.stopping_distance_m - range_m if relevant else -math.inf


def steering_held(state: CoreState, speed_mps: float, params: CoreParams) -> bool:
    """A steering path is latched and the car has not stopped yet (module docstring, Latch)."""
    return state.steer_curvature_1pm is not None and speed_mps > params.standstill_speed_mps


def _toward(previous: float, target: float, step: float) -> float:
    return previous + min(step, max(-step, target - previous))


def steering(state: CoreState, mode: Mode, region: RegionCycle | None, shortfall_m: float, inputs_wheel_rad: float,
             yaw_rate_radps: float, speed_mps: float, decel_mps2: float, params: CoreParams) -> Steering:
    """This cycle's request (module docstring); ``shortfall_m``: how far braking falls short of the line's object;
    ``inputs_wheel_rad``: the driver's steering-wheel angle."""
    if not params.steering_authority:
        return NO_STEERING
    held, evasion = latched(state, mode, region, shortfall_m, params)
    kappa = None if held is None else tracking_curvature(held, evasion, speed_mps)
    rp = params.region
    target = 0.0
    if kappa is not None:
        measured = yaw_rate_radps / speed_mps if speed_mps > rp.yaw_rate_min_speed_mps else kappa
        road_wheel = math.atan(kappa * rp.wheelbase_m) + math.atan((kappa - measured) * rp.wheelbase_m)
        target = road_wheel - inputs_wheel_rad / params.steering_ratio
        target = min(REQUEST_RANGE_RAD[1], max(REQUEST_RANGE_RAD[0], target))
    request = _toward(state.steer_request_rad, target, rp.steer_rate_max_radps * params.cycle_s)
    decel = math.inf if kappa is None else _braking_mps2(kappa, evasion, speed_mps, yaw_rate_radps, decel_mps2)
    return Steering(held, request, held is not None or request != 0.0, decel,
                    advanced(evasion, speed_mps, yaw_rate_radps, params.cycle_s))
