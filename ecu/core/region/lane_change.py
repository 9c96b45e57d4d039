"""Giving way on a lane change (issue 23's ``merge``): the car that moves over gives way to the car in the lane.

Traffic law puts the duty on the driver who changes lanes, not on the one in the lane he enters: the
Vienna Convention on Road Traffic (1968), art. 14(1), asks a driver who wishes to move over to the right
or to the left on the carriageway to first make sure that he can do so without endangering other road
users behind, ahead or about to pass him (paraphrased); the German StVO section 7(5) lets a lane be
changed only when endangering other road users is excluded, and section 7(4) (the zip merge) has the
vehicles of a lane that ends merge in turn *behind* a vehicle of the through lane (both paraphrased, not
quoted; the wording is not checked here). So under ``[ecu] way_out = "right_of_way"`` the car whose
lane ends tightens against the car beside it and drops behind; the car in the through lane does not.

**How the ECU knows it changes lanes** (it has no map, and its assumed road follows its own curvature,
:func:`ecu.core.planar.assumed_road`): its path turns toward a vehicle going its way, which does not turn
with it. A track counts when it is

* a moving vehicle (the crossing rule's classes, :data:`ecu.core.region.crossing.VEHICLE_CLASSES`) going
  our way: its velocity within ``CROSSING_ANGLE_RAD`` of our heading (a vehicle crossing at a larger
  angle is the crossing rule's, :func:`ecu.core.region.crossing.crossing_mask`);
* beside us or ahead, in a neighbour lane: its nearest point beyond our side (``width_m / 2``) and within
  one and a half lanes (``lane_width_m``) of our axis (a car in the next lane but one, or in ours, stays out);
* toward our turn: our current curvature ``kappa`` turns toward its side, strongly enough to take our
  path half a lane over within ``way_out_path_m`` (``|kappa| >= lane_width_m / way_out_path_m^2``:
  0.0039 1/m with the defaults; a lane change, not the drift of a car keeping its lane);
* not turning with us: its heading relative to ours is turned against our turn (``phi * kappa < 0``). A
  car beside us in a bend we share turns as we do (``phi`` about 0) and stays out, as long as the two
  turn alike (a known limit: with noisy velocities it may flicker in and out).

Only tightening follows the rule: the contingency keeps our stopping path disjoint from every object, the
car in the lane included. The rule holds while the path turns toward the other car (the start of the lane
change, when the driver must make sure it is safe); on the way back to straight it no longer counts (the
ECU keeps no memory of the manoeuvre), and the contingency alone stays.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Sequence

import numpy as np

from .objects import ObjectSet

#: a vehicle's velocity within this of our heading goes our way (the crossing rule's threshold)
SAME_WAY_ANGLE_RAD = math.radians(30.0)


class LaneChange(NamedTuple):
    """Our side of a lane change: the current curvature (1/m, left positive), our width, the assumed lane width
    and the path over which the change must take us half a lane over (``way_out_path_m``), all SI."""

    curvature_1pm: float
    width_m: float
    lane_width_m: float
    path_m: float


def lane_change_mask(objects: ObjectSet, vehicle: np.ndarray, lateral_m: np.ndarray, ours: LaneChange) -> np.ndarray:
    """Which of ``objects`` (``vehicle``: which are vehicles; ``lateral_m``: their tracks' nearest points' y) we
    move over toward (module docstring)."""
    kappa, path_m = ours.curvature_1pm, ours.path_m
    if path_m <= 0.0 or abs(kappa) < ours.lane_width_m / (path_m * path_m):
        return np.zeros(objects.centre.shape, dtype=bool)
    side = math.copysign(1.0, kappa)
    offset = lateral_m * side
    same_way = objects.axis.real >= math.cos(SAME_WAY_ANGLE_RAD)
    against_our_turn = objects.axis.imag * side < 0.0
    beside = (offset >= 0.5 * ours.width_m) & (offset <= 1.5 * ours.lane_width_m)
    return objects.moving & vehicle & same_way & against_our_turn & beside


def vehicle_mask(size_classes: Sequence[int], classes: frozenset[int]) -> np.ndarray:
    """Which size classes are among ``classes``."""
    return np.array([c in classes for c in size_classes], dtype=bool)
