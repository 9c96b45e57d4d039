"""The planner: the driver's command, bounded by the strategy, and its stopping path's disjointness.

Each cycle, for the speed estimate and the model deceleration D of this cycle
(the strategy's, :mod:`ecu.core.strategies`):

1. relevance: an object outside our path is no object
   (:mod:`ecu.core.relevance`, decided once per cycle by the caller);
2. proximity to the contingency boundary: behind a moving object the
   relative form (:func:`ecu.core.relative_stop.moving_proximity`), else the
   absolute one (:func:`ecu.core.proximity.proximity`);
3. the strategy's bound at that proximity (``tighten``), and the command
   ``min(a_drv, a_hi)`` (:mod:`ecu.core.intent`);
4. that command's stopping path: to zero relative speed behind a moving
   object (:func:`ecu.core.relative_stop.relative_approach_m`), to standstill
   otherwise (:func:`ecu.core.stopping_path.stopping_distance_m`), and whether
   it is disjoint, also with the release margin
   (``contingency_release_ratio``, ``contingency_release_speed_mps``).
"""

from __future__ import annotations

from typing import NamedTuple

from .intent import driver_accel_mps2
from .params import CoreParams
from .proximity import proximity
from .relative_stop import (clear_of_lead_m, is_moving, lead_region_applies, moving_proximity, relative_approach_m,
                            relative_disjoint)
from .relevance import object_in_path
from .stopping_path import is_disjoint, stopping_distance_m
from .types import CoreInputs


class Plan(NamedTuple):
    """The planner's result for this cycle, before the mode and the gate."""

    proximity: float
    throttle_limit_pct: float
    decel_request_mps2: float
    tightening_restricts: bool
    stopping_distance_m: float
    disjoint: bool
    #: disjoint with the release margin (``contingency_release_ratio`` >= 1, so released implies
    #: disjoint) and slow enough: a contingency that was active may end.
    released: bool


def plan_cycle(speed_mps: float, inputs: CoreInputs, params: CoreParams,
               model_decel_mps2: float | None = None) -> Plan:
    """Tighten the driver's command (if the strategy says so) and check its stopping path.

    ``model_decel_mps2`` overrides the model deceleration D (None: the strategy's fixed one).
    """
    relevant = inputs.object_valid and object_in_path(inputs, speed_mps, params)
    decel = params.model_decel_mps2 if model_decel_mps2 is None else model_decel_mps2
    return plan(speed_mps, inputs, relevant, decel, params)


def plan(speed_mps: float, inputs: CoreInputs, relevant: bool, decel_mps2: float, params: CoreParams) -> Plan:
    """:func:`plan_cycle` for an object already judged ``relevant`` (valid and in our path) and D given.

    Behind a moving object the stopping path ends at zero relative speed (:mod:`ecu.core.relative_stop`),
    otherwise at standstill (:mod:`ecu.core.stopping_path`).
    """
    rate, range_m = inputs.object_range_rate_mps, inputs.object_range_m
    moving = relevant and is_moving(speed_mps, rate, params)
    if moving:
        p = moving_proximity(range_m, rate, params, decel_mps2, speed_mps)
    else:
        p = proximity(relevant, range_m, speed_mps, params, decel_mps2)
    bound = params.strategy_rules.tighten(p, params)
    command = min(driver_accel_mps2(inputs.accel_pedal, inputs.brake_pedal, params), bound.accel_upper_mps2)
    ratio = params.contingency_release_ratio
    if moving:  # clear of the object's path at constant speed and, while closing, of its own stopping region
        distance = relative_approach_m(rate, command, params, decel_mps2)
        clear = (not lead_region_applies(speed_mps, rate, params)
                 or clear_of_lead_m(speed_mps, command, range_m, rate, params, decel_mps2) >= 0.0)
        disjoint = clear and relative_disjoint(distance, range_m, params)
        release = clear and relative_disjoint(distance * ratio, range_m, params)
    else:
        distance = stopping_distance_m(speed_mps, command, params.hold_time_s, decel_mps2)
        disjoint = is_disjoint(distance, relevant, range_m, params)
        release = is_disjoint(distance * ratio, relevant, range_m, params)
    return Plan(p, bound.throttle_limit_pct, bound.decel_request_mps2, bound.restricts, distance, disjoint,
                speed_mps <= params.contingency_release_speed_mps and release)
