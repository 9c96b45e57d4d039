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

**Cost** (issue 22: the step with 8 tracks within 100 µs): numpy's per-call overhead, not arithmetic, so
the work is a few calls on whole arrays (:func:`evaluate`: one family, one footprint, one separation of
every object, row and pose). When an object is :func:`within_reach` the steering rows are evaluated
with the base rows in one call (one evaluation of 16 rows costs less than two of 3 and 13), else only
if rules 1 and 2 fail; either order gives the same decision (``tests/ecu/region/test_evaluation_order.py``).
The driver's gaps to each object are kept (``driver_gaps_m``), so :mod:`ecu.core.planar` judges the
driver's path over a subset of the tracks without a second evaluation (:func:`driver_disjoint_without`); so are
every object's gaps to the decision's rows (``object_gaps_m``), which the crossing rule reads
(:func:`ecu.core.region.crossing.crossing_proximity`).
"""

from __future__ import annotations

import bisect
import math
from enum import IntEnum
from typing import NamedTuple, Sequence

import numpy as np

from ..stopping_path import stopping_distance_m
from .evasion import evasion_family, evasion_params
from .objects import ObjectSet, TrackBox, boxes_as_set, object_box
from .overlap import Footprint, corner_points, footprint, object_gaps, speed_at_mps
from .params import GRAVITY_MPS2, RegionParams
from .paths import (DRIVER, FIRST_STEER, LANE, NOMINAL, EgoState, PathSet, current_curvature, driver_curvature,
                    path_family)
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
    #: per object and pose, the driver's row's gaps ``(K, M)`` (:func:`driver_disjoint_without`)
    driver_gaps_m: np.ndarray = np.empty((0, 0))
    #: per object, row of ``paths`` and pose, the gaps ``(K, N, M)`` (:func:`ecu.core.region.overlap.object_gaps`)
    object_gaps_m: np.ndarray = np.empty((0, 0, 0))
    #: the chosen path is an evasive lane change (:mod:`ecu.core.region.evasion`): its lateral offset (m, left
    #: positive; 0 if not) and where its S begins (m)
    evasion_offset_m: float = 0.0
    evasion_lead_m: float = 0.0


def clearances(paths: PathSet, objects: ObjectSet, box: Footprint) -> tuple[np.ndarray, np.ndarray]:
    """(per row and pose the smallest gap ``(N, M)``, per row the clearance ``(N,)``); +inf without objects."""
    per_pose, clearance, _ = separations(paths, objects, box)
    return per_pose, clearance


def separations(paths: PathSet, objects: ObjectSet, box: Footprint) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`clearances` and, per object, row and pose, the gaps ``(K, N, M)`` (:func:`driver_disjoint_without`
    reads the driver's row's)."""
    if objects.centre.size == 0:
        rows, poses = paths.position.shape
        per_pose = np.full((rows, poses), np.inf)
        return per_pose, per_pose[:, 0], np.empty((0, rows, poses))  # no objects: (0, N, M)
    g = object_gaps(paths, objects, box)
    per_pose = g.min(axis=0)
    return per_pose, per_pose.min(axis=1), g


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
    samples = per_pose.shape[1]
    stops: list[float] = paths.stop_m.tolist()
    s_prev = [stop * (first / samples) for stop, first in zip(stops, hit.argmax(axis=1).tolist())]
    return np.where(hit.any(axis=1), speed_at_mps(paths, s_prev), 0.0)


def admissible_steering(paths: PathSet, box: Footprint, objects: ObjectSet, road: Road | None) -> np.ndarray:
    """Steering rows that are followable and, with a road, stay in the allowed span."""
    if road is None:
        return paths.feasible
    span = allowed_span(road, lateral_offsets(road, objects.centre))
    return paths.feasible & on_road(road, corner_points(paths, box), span)


def driver_disjoint_without(decision: RegionDecision, skip: int | None) -> bool:
    """Rule 1 over every object but the ``skip``-th (None: over all): the decision over a subset of the tracks,
    without a second evaluation (each object's box depends on its own track alone)."""
    disjoint: list[bool] = np.logical_and.reduce(decision.driver_gaps_m >= 0.0, axis=1).tolist()  # per object
    return all(ok for k, ok in enumerate(disjoint) if k != skip)


class Evaluation(NamedTuple):
    """Rows of a family, their footprint, their clearances (:func:`clearances`) and every object's gaps to them."""

    paths: PathSet
    box: Footprint
    per_pose: np.ndarray
    clearance: np.ndarray
    gaps: np.ndarray

    def rows(self, rows: slice) -> Evaluation:
        """The ``rows`` of every field."""
        p, box = self.paths, self.box
        paths = PathSet(p.curvature_1pm[rows], p.max_curvature_1pm[rows], p.accel_mps2[rows], p.hold_m[rows],
                        p.hold_speed_mps[rows], p.stop_m[rows], p.feasible[rows], p.position[rows], p.heading[rows],
                        p.friction_mps2)
        return Evaluation(paths, Footprint(box.mid_x_m[rows], box.half_x_m[rows], box.half_y_m[rows]),
                          self.per_pose[rows], self.clearance[rows], self.gaps[:, rows])


def within_reach(ego: EgoState, boxes: Sequence[tuple[float, ...]], params: RegionParams) -> bool:
    """Whether an object's box (:func:`ecu.core.region.objects.object_box`) may reach the driver's stopping path: a
    guess whether rules 1 and 2 fail, which orders the work (the steering rows built with the base rows, or after
    them if needed), never the result. Scalar code: for eight boxes cheaper than numpy's calls.

    A box's bounding half extent ``a + b`` against the nominal row's straight stopping distance and the
    footprint's reach ahead, and across against the ego's width and the driver's arc's offset ``|kappa_0| s^2 / 2``."""
    friction = min(ego.decel_mps2, ego.friction_mu * GRAVITY_MPS2)
    ahead = (stopping_distance_m(ego.speed_mps, params.driver_max_accel_mps2, params.hold_time_s, friction)
             + params.rear_axle_to_front_m + params.standoff_m)
    curvature = max(abs(current_curvature(ego, params)), abs(driver_curvature(ego, params)))
    across = params.width_m + 0.5 * curvature * ahead * ahead
    return any(x - (a + b) < ahead and abs(y) - (a + b) < across for x, y, _, _, a, b, _ in boxes)


def evaluate(ego: EgoState, road_curvature_1pm: float, objects: ObjectSet, params: RegionParams,
             rows: tuple[bool, bool]) -> tuple[Evaluation, np.ndarray]:
    """The family's (base, steering) ``rows`` evaluated against the objects, and the driver's per-object gaps."""
    paths = path_family(ego, road_curvature_1pm, params, base=rows[0], steering=rows[1])
    box = footprint(paths, params)
    per_pose, clearance, gaps = separations(paths, objects, box)
    return Evaluation(paths, box, per_pose, clearance, gaps), gaps[:, DRIVER]


def _result(kind: Contingency, row: int, ctx: tuple, clearance: np.ndarray, impact: float,
            steering: bool = False, evasion: tuple[float, float] = (0.0, 0.0)) -> RegionDecision:
    """The decision for ``row`` of ``ctx``'s paths (with their footprint and every object's gaps to them);
    ``clearance[DRIVER]`` and the driver's distance from the base."""
    paths, box, gaps, params, base = ctx
    decel = 0.0 if kind is Contingency.DRIVER_PATH else contingency_decel_mps2(paths, row, params)
    return RegionDecision(kind, row, float(paths.curvature_1pm[row]), decel, float(clearance[row]), impact,
                          float(paths.stop_m[row]), base.driver_disjoint, base.driver_stopping_distance_m,
                          base.proximity, paths, box, base.objects, steering, base.driver_gaps_m, gaps,
                          *evasion)


def _free_sides(road: Road, lane: int, objects: ObjectSet) -> tuple[float, ...]:
    """The sides (1: left, -1: right) where the road's allowed span (:func:`ecu.core.region.road.allowed_span`)
    goes beyond our ``lane``: a lane change toward any other side is never admissible, so it is not built (a
    third of the urgent step's cost with one free lane)."""
    span = allowed_span(road, lateral_offsets(road, objects.centre))
    left, right = span[1] > road.boundaries_m[lane], span[0] < road.boundaries_m[lane - 1]
    return (1.0, -1.0) if left and right else (1.0,) if left else (-1.0,) if right else ()


def _evasion(ego: EgoState, road: Road | None, ctx: tuple) -> RegionDecision | None:
    """Rule 3 over the evasive lane changes (:mod:`ecu.core.region.evasion`) when no arc is disjoint: the
    admissible disjoint one with the largest clearance, or None. Needs a road (its own lane's width)."""
    if road is None:
        return None
    params, base = ctx
    params = evasion_params(params)
    lane = bisect.bisect_right(road.boundaries_m, 0.0)
    if lane == 0 or lane == len(road.boundaries_m):
        return None
    sides = _free_sides(road, lane, base.objects)
    if not sides:
        return None
    paths, offset, lead = evasion_family(ego, road.boundaries_m[lane] - road.boundaries_m[lane - 1], params, sides)
    box = footprint(paths, params)
    _, clearance, gaps = separations(paths, base.objects, box)
    disjoint = admissible_steering(paths, box, base.objects, road) & (clearance >= 0.0)
    if not disjoint.any():
        return None
    row = int(np.argmax(np.where(disjoint, clearance, -np.inf)))
    return _result(Contingency.STEER_AND_BRAKE, row, (paths, box, gaps, params, base), clearance, 0.0,
                   steering=True, evasion=(float(offset[row]), float(lead[row])))


def _steer_or_least_impact(steering: Evaluation, speeds: np.ndarray, lane: tuple[float, float],
                           road: Road | None, ctx: tuple) -> RegionDecision:
    """Rules 3 and 4 over the ``steering`` rows and their impact ``speeds``, then (rule 3 still) the evasive lane
    changes; ``lane``: the lane row's (clearance, impact speed); ``ctx``: (params, base decision, ego)."""
    params, base, ego = ctx
    paths, box, clearance = steering.paths, steering.box, steering.clearance
    ok = admissible_steering(paths, box, base.objects, road)
    result_ctx = (paths, box, steering.gaps, params, base)
    disjoint = ok & (clearance >= 0.0)
    if disjoint.any():
        row = int(np.argmax(np.where(disjoint, clearance, -np.inf)))
        return _result(Contingency.STEER_AND_BRAKE, row, result_ctx, clearance, 0.0, steering=True)
    evasion = _evasion(ego, road, (params, base))
    if evasion is not None:
        return evasion
    speeds = np.where(ok, speeds, np.inf)
    row = int(np.argmin(speeds))
    if speeds[row] < lane[1]:
        return _result(Contingency.LEAST_IMPACT, row, result_ctx, clearance, float(speeds[row]), steering=True)
    return _lane_least_impact(params, base, lane)


def _lane_least_impact(params: RegionParams, base: RegionDecision, lane: tuple[float, float]) -> RegionDecision:
    """Rule 4 on the lane row alone: braking in lane, its first contact's speed (``lane``: clearance, speed)."""
    clearance = np.full(base.paths.curvature_1pm.shape, lane[0])
    return _result(Contingency.LEAST_IMPACT, LANE, (base.paths, base.box, base.object_gaps_m, params, base),
                   clearance, lane[1])


def _steering_rows(ego: EgoState, road_curvature_1pm: float, params: RegionParams, whole: Evaluation,
                   base: RegionDecision) -> tuple[Evaluation, np.ndarray, float]:
    """(the steering rows, their impact speeds, the lane row's impact speed): from ``whole`` if it holds them,
    else evaluated now."""
    if len(whole.clearance) > len(base.paths.curvature_1pm):
        speeds = impact_speeds_mps(whole.paths, whole.per_pose)
        return whole.rows(slice(FIRST_STEER, None)), speeds[FIRST_STEER:], float(speeds[LANE])
    steering, _ = evaluate(ego, road_curvature_1pm, base.objects, params, (False, True))
    lane_speed = float(impact_speeds_mps(whole.paths, whole.per_pose)[LANE])
    return steering, impact_speeds_mps(steering.paths, steering.per_pose), lane_speed


def decide(ego: EgoState, tracks: Sequence[TrackBox], road: Road | None, params: RegionParams,
           steer: bool = True) -> RegionDecision:
    """The rules of the module docstring; the steering rows only with ``steer`` (steering authority), judged only
    when rules 1 and 2 fail, and built with the base rows (one evaluation costs less than two) when an object
    is :func:`within_reach`, else after them when needed (:func:`decide_boxes`). A standing track's box stands
    along the ``road`` (:func:`ecu.core.region.objects.standing_heading_rad`)."""
    boxes = [object_box(track, ego.speed_mps, params, road) for track in tracks]
    return decide_boxes(ego, boxes, road, params, (steer, steer and within_reach(ego, boxes, params)))


def decide_boxes(ego: EgoState, boxes: Sequence[tuple[float, ...]], road: Road | None, params: RegionParams,
                 steer: tuple[bool, bool]) -> RegionDecision:
    """:func:`decide` over :func:`ecu.core.region.objects.object_box` es; ``steer``: (steering authority, the
    steering rows evaluated with the base rows)."""
    objects, road_k = boxes_as_set(boxes), 0.0 if road is None else road.curvature_1pm
    whole, driver_gaps = evaluate(ego, road_k, objects, params, (True, steer[1]))
    first = whole.rows(slice(None, FIRST_STEER)) if steer[1] else whole
    paths, clearance = first.paths, first.clearance
    driver_disjoint = bool(clearance[DRIVER] >= 0.0)
    base = RegionDecision(Contingency.DRIVER_PATH, DRIVER, float(paths.curvature_1pm[DRIVER]), 0.0,
                          float(clearance[DRIVER]), 0.0, float(paths.stop_m[DRIVER]), driver_disjoint,
                          float(paths.stop_m[DRIVER]), proximity_of(float(clearance[NOMINAL]), params),
                          paths, first.box, objects, False, driver_gaps, first.gaps)
    if driver_disjoint:
        return base
    if clearance[LANE] >= 0.0 and paths.feasible[LANE]:
        return _result(Contingency.BRAKE_IN_LANE, LANE, (paths, first.box, first.gaps, params, base), clearance,
                       0.0)
    if not steer[0]:
        return _lane_least_impact(params, base, (float(clearance[LANE]),
                                                 float(impact_speeds_mps(paths, first.per_pose)[LANE])))
    steering, speeds, lane_speed = _steering_rows(ego, road_k, params, whole, base)
    return _steer_or_least_impact(steering, speeds, (float(clearance[LANE]), lane_speed), road, (params, base, ego))
