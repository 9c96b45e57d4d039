"""Stopping Path Disjointness in the plane and the choice of contingency (issue 22, item 1).

Johnson 2019, Prop. 1: the ego keeps at least one stopping path disjoint from the stopping regions
of all other agents (:mod:`ecu.core.region.objects`), and invokes a contingency when the driver's
would not be. The choice, in the issue's order:

1. ``DRIVER_PATH``: the driver's path (current curvature, command held for ``t_h``) braked along is
   disjoint: no intervention (the 1-D core's ``disjoint``);
2. ``BRAKE_IN_LANE``: braking along the lane's curvature is disjoint;
3. ``STEER_AND_BRAKE``: of the steering rows that are followable (friction circle), within UN
   R79's limits as applied here (:mod:`ecu.core.region.params`), on the road and out of lanes other
   tracks occupy (:mod:`ecu.core.region.road`), and disjoint, the one with the largest clearance;
4. ``LEAST_IMPACT``: none is disjoint: of the lane row and the admissible steering rows, the one
   whose first contact comes at the lowest speed (:func:`ecu.core.region.overlap.speed_at_mps`).

Without a road every steering row is admissible; without steering authority (``steer=False``) none is,
and rule 4 takes the lane row. The contingency kinds are the DBC's ``EcuRegionStatus.Contingency``
values (its ``VAL_`` adds ``NOT_EVALUATED``, sent without planar tracks; a test keeps the two equal).
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import NamedTuple, Sequence

import numpy as np

from .objects import ObjectSet, TrackBox, object_set
from .overlap import Footprint, corner_points, footprint, gaps, speed_at_mps
from .params import RegionParams
from .paths import DRIVER, LANE, NOMINAL, EgoState, PathSet, path_family
from .road import Road, allowed_span, lateral_offsets, on_road


class Contingency(IntEnum):
    """The chosen stopping path's kind, in the order of the rules."""

    DRIVER_PATH = 0
    BRAKE_IN_LANE = 1
    STEER_AND_BRAKE = 2
    LEAST_IMPACT = 3


class RegionDecision(NamedTuple):
    """One evaluation: the choice, its numbers, and what a bird's-eye view draws (:mod:`.drawing`).

    ``row`` indexes ``paths``: the driver's, nominal and lane rows (:data:`ecu.core.region.paths.DRIVER` ..)
    for the first two kinds and a least-impact lane choice, the steering rows alone otherwise."""

    kind: Contingency
    row: int
    curvature_1pm: float
    decel_mps2: float
    clearance_m: float
    impact_speed_mps: float
    stopping_distance_m: float
    driver_disjoint: bool
    driver_stopping_distance_m: float
    proximity: float
    paths: PathSet
    box: Footprint
    objects: ObjectSet
    #: the chosen path is a steering row (STEER_AND_BRAKE, or LEAST_IMPACT on a steering row)
    steering: bool = False


def clearances(paths: PathSet, objects: ObjectSet, box: Footprint) -> tuple[np.ndarray, np.ndarray]:
    """(per row and pose the smallest gap ``(N, M)``, per row the clearance ``(N,)``); +inf without objects."""
    if objects.centre.size == 0:
        per_pose = np.full(paths.position.shape, np.inf)
        return per_pose, per_pose[:, 0]
    per_pose = gaps(paths, objects, box).min(axis=2)
    return per_pose, per_pose.min(axis=1)


def proximity_of(clearance_m: float, params: RegionParams) -> float:
    """p = clamp(1 - m / proximity_margin_m, 0, 1), m the nominal row's clearance (:mod:`ecu.core.proximity`)."""
    return min(1.0, max(0.0, 1.0 - clearance_m / params.proximity_margin_m))


def contingency_decel_mps2(paths: PathSet, row: int, params: RegionParams) -> float:
    """Full braking, or on a curve what the friction circle leaves: ``min(C, sqrt(A^2 - (v_h^2 kappa)^2))``."""
    kappa = float(paths.curvature_1pm[row])
    if kappa == 0.0:
        return params.contingency_decel_mps2
    lateral = float(paths.hold_speed_mps[row]) ** 2 * abs(kappa)
    return min(params.contingency_decel_mps2, math.sqrt(max(0.0, paths.friction_mps2 ** 2 - lateral ** 2)))


def impact_speeds_mps(paths: PathSet, per_pose: np.ndarray) -> np.ndarray:
    """Per row: the speed at the start of the first box that touches an object (0 if none touches)."""
    hit = per_pose < 0.0
    first = hit.argmax(axis=1)
    s_prev = paths.stop_m * (first / per_pose.shape[1])
    speed = speed_at_mps(paths, s_prev)
    return np.where(hit.any(axis=1), speed, 0.0)


def admissible_steering(paths: PathSet, box: Footprint, objects: ObjectSet, road: Road | None) -> np.ndarray:
    """Steering rows that are followable and, with a road, stay in the allowed span."""
    if road is None:
        return paths.feasible
    span = allowed_span(road, lateral_offsets(road, objects.centre))
    return paths.feasible & on_road(road, corner_points(paths, box), span)


def _result(kind: Contingency, row: int, ctx: tuple, clearance: np.ndarray, impact: float,
            steering: bool = False) -> RegionDecision:
    """The decision for ``row`` of ``ctx``'s paths; ``clearance[DRIVER]`` and the driver's distance from the base."""
    paths, box, objects, params, base = ctx
    decel = 0.0 if kind is Contingency.DRIVER_PATH else contingency_decel_mps2(paths, row, params)
    return RegionDecision(kind, row, float(paths.curvature_1pm[row]), decel, float(clearance[row]), impact,
                          float(paths.stop_m[row]), base.driver_disjoint, base.driver_stopping_distance_m,
                          base.proximity, paths, box, objects, steering)


def _lane_least_impact(params: RegionParams, base: RegionDecision, lane_per_pose: np.ndarray) -> RegionDecision:
    """Rule 4 on the lane row alone: braking in lane, its first contact's speed."""
    lane_speed = float(impact_speeds_mps(base.paths, lane_per_pose)[LANE])
    lane_clearance = np.full(base.paths.curvature_1pm.shape, base.clearance_m)
    lane_clearance[LANE] = float(lane_per_pose[LANE].min())
    return _result(Contingency.LEAST_IMPACT, LANE, (base.paths, base.box, base.objects, params, base),
                   lane_clearance, lane_speed)


def _steer_or_least_impact(ego: EgoState, road: Road | None, params: RegionParams,
                           base: RegionDecision, lane_per_pose: np.ndarray) -> RegionDecision:
    """Rules 3 and 4: the steering rows only; the lane row's result comes from ``base``."""
    paths = path_family(ego, 0.0, params, base=False, steering=True)
    box = footprint(paths, params)
    per_pose, clearance = clearances(paths, base.objects, box)
    ok = admissible_steering(paths, box, base.objects, road)
    ctx = (paths, box, base.objects, params, base)
    disjoint = ok & (clearance >= 0.0)
    if disjoint.any():
        row = int(np.argmax(np.where(disjoint, clearance, -np.inf)))
        return _result(Contingency.STEER_AND_BRAKE, row, ctx, clearance, 0.0, steering=True)
    speeds = np.where(ok, impact_speeds_mps(paths, per_pose), np.inf)
    lane_speed = float(impact_speeds_mps(base.paths, lane_per_pose)[LANE])
    row = int(np.argmin(speeds))
    if speeds[row] < lane_speed:
        return _result(Contingency.LEAST_IMPACT, row, ctx, clearance, float(speeds[row]), steering=True)
    return _lane_least_impact(params, base, lane_per_pose)


def decide(ego: EgoState, tracks: Sequence[TrackBox], road: Road | None, params: RegionParams,
           steer: bool = True) -> RegionDecision:
    """The rules of the module docstring; the steering rows are built only when rules 1 and 2 fail, and only
    with ``steer`` (steering authority)."""
    objects = object_set(tracks, ego.speed_mps, params)
    paths = path_family(ego, 0.0 if road is None else road.curvature_1pm, params, steering=False)
    box = footprint(paths, params)
    per_pose, clearance = clearances(paths, objects, box)
    driver_disjoint = bool(clearance[DRIVER] >= 0.0)
    base = RegionDecision(Contingency.DRIVER_PATH, DRIVER, float(paths.curvature_1pm[DRIVER]), 0.0,
                          float(clearance[DRIVER]), 0.0, float(paths.stop_m[DRIVER]), driver_disjoint,
                          float(paths.stop_m[DRIVER]), proximity_of(float(clearance[NOMINAL]), params),
                          paths, box, objects)
    if driver_disjoint:
        return base
    if clearance[LANE] >= 0.0 and paths.feasible[LANE]:
        return _result(Contingency.BRAKE_IN_LANE, LANE, (paths, box, objects, params, base), clearance, 0.0)
    if not steer:
        return _lane_least_impact(params, base, per_pose)
    return _steer_or_least_impact(ego, road, params, base, per_pose)
