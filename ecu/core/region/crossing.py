"""Constraint tightening against crossing vehicles (issue 23): the proximity of the nominal path to the stopping
regions of vehicles that cross it.

The paper's tightening biases the nominal bounds toward the contingency bounds "as proximity grows". On the
line the proximity is that of the one object in our path (:mod:`ecu.core.proximity`); in the plane the
region reports the nominal row's proximity to every object (:func:`ecu.core.region.decision.proximity_of`),
but a car in the next lane, a parked car or a pedestrian at the kerb would then bound the throttle of a car
that has nothing to avoid. What the plane adds to tightening is the case the line cannot see: a **vehicle
crossing our path**. Its stopping region (:mod:`ecu.core.region.objects`) sweeps across our path, and two
cars that each keep only the contingency fall into the reciprocal dance at a crossing (``crd fleet
crossing``: both brake, both release as the other's region shrinks, both accelerate, and they collide).

A track counts when it is

* moving (its speed over ground above ``moving_object_speed_mps``),
* a vehicle (the DBC's size class MOTORCYCLE, CAR or TRUCK: a pedestrian's or a cyclist's region is
  metres, and the contingency alone handles it as before),
* crossing: its velocity at least ``CROSSING_ANGLE_RAD`` (30 degrees) off our heading and off the
  opposite one (oncoming and overtaking traffic, in a curve too, stay out),
* not moving away from our path (``y v_y <= 0``, y its centre's lateral offset: a lead car turning off,
  already beside our axis and leaving it, stays out).

Under ``right_of_way`` a car that changes lanes also gives way to the vehicle in the lane it moves into, which
goes its way and so is not crossing (:mod:`ecu.core.region.lane_change`, ``LANE_CHANGE_WAY_OUTS``).

The proximity is :func:`~ecu.core.region.decision.proximity_of` of the nominal row's clearance to those
tracks' regions alone; the strategy's ``tighten`` turns it into the bound (``none`` and ``conservative`` do
not tighten, so nothing changes for them).
"""

from __future__ import annotations

import math
from types import MappingProxyType
from typing import Callable, Mapping, Sequence

import numpy as np

from can_dbc.contract import enumeration

from .decision import RegionDecision, proximity_of
from .objects import ObjectSet, TrackBox
from .overlap import row_gaps
from .params import RegionParams
from .paths import NOMINAL
from .reciprocal import reciprocal_mask

CROSSING_ANGLE_RAD = math.radians(30.0)
#: the DBC's Track<i>SizeClass values of vehicles
VEHICLE_CLASSES = frozenset(value for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()
                            if name in ("MOTORCYCLE", "CAR", "TRUCK"))


def crossing_mask(objects: ObjectSet, size_classes: Sequence[int]) -> np.ndarray:
    """Which of ``objects`` (in the order of their tracks, whose classes are ``size_classes``) count. Scalar code
    (compiled, ``setup.py``): for eight objects cheaper than numpy's calls."""
    across_min = math.sin(CROSSING_ANGLE_RAD)
    axes: list[complex] = objects.axis.tolist()
    centres: list[complex] = objects.centre.tolist()
    moving: list[bool] = objects.moving.tolist()
    return np.array([m and c in VEHICLE_CLASSES and abs(u.imag) >= across_min and o.imag * u.imag <= 0.0
                     for m, c, u, o in zip(moving, size_classes, axes, centres)], dtype=bool)


#: a way-out rule: (the tracks' boxes, the tracks, our speed, the parameters) -> the tracks it tightens against
WayOutRule = Callable[[ObjectSet, Sequence[TrackBox], float, RegionParams], np.ndarray]


def _every_crossing(objects: ObjectSet, tracks: Sequence[TrackBox], speed_mps: float,
                    params: RegionParams) -> np.ndarray:
    return np.ones(objects.centre.shape, dtype=bool)


def _from_the_right(objects: ObjectSet, tracks: Sequence[TrackBox], speed_mps: float,
                    params: RegionParams) -> np.ndarray:
    return objects.centre.imag < 0.0


def _reciprocal(objects: ObjectSet, tracks: Sequence[TrackBox], speed_mps: float,
                params: RegionParams) -> np.ndarray:
    return reciprocal_mask(tracks, speed_mps, params)


#: ``[ecu] way_out`` -> which crossing vehicles the ego tightens against (the contingency, the plain method's
#: disjointness, holds against every object whatever the rule)
WAY_OUT_RULES: Mapping[str, WayOutRule] = MappingProxyType({
    "none": _every_crossing,           # the plain method: every crossing vehicle
    "right_of_way": _from_the_right,   # give way to the right (Vienna Convention 1968, art. 18(4)(a))
    "reciprocal": _reciprocal,         # ORCA's split: only where our half is to slow (ecu.core.region.reciprocal)
})
#: the way-out rules under which a car that changes lanes also gives way to the vehicle in the lane it moves
#: into (Vienna Convention 1968, art. 14(1); ecu.core.region.lane_change): none keeps the plain method
LANE_CHANGE_WAY_OUTS = frozenset({"right_of_way"})


def crossing_proximity(decision: RegionDecision, tracks: Sequence[TrackBox], speed_mps: float, params: RegionParams,
                       way_out: str = "none", path_ahead_m: float = 0.0, also: np.ndarray | None = None) -> float:
    """The nominal row's proximity to the crossing vehicles' regions that ``way_out`` keeps (module
    docstring), and to those of ``also`` (a mask over the objects: the vehicles of the lane we move into,
    :mod:`ecu.core.region.lane_change`), each region extended ``path_ahead_m`` further along its velocity (a
    way-out rule yields to the other car's way, not only to where it could stop); 0 without any. ``tracks``:
    the boxes' tracks, in their order; ``speed_mps``: ours."""
    objects = decision.objects
    if objects.centre.size == 0:
        return 0.0
    mask = crossing_mask(objects, [t.size_class for t in tracks]) & \
        WAY_OUT_RULES[way_out](objects, tracks, speed_mps, params)
    if also is not None:
        mask = mask | also
    if not mask.any():
        return 0.0
    if path_ahead_m > 0.0:  # the regions extended: the nominal row's gaps to them worked out
        subset = ObjectSet(*(field[mask] for field in objects))
        subset = subset._replace(centre=subset.centre + 0.5 * path_ahead_m * subset.axis,
                                 half_length_m=subset.half_length_m + 0.5 * path_ahead_m)
        clearance = float(row_gaps(decision.paths, subset, decision.box, NOMINAL).min())
    else:  # the regions as the decision judged them: its gaps, read
        clearance = float(decision.object_gaps_m[mask, NOMINAL].min())
    return proximity_of(clearance, params)
