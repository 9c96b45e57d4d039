"""Relevance: is the radar's object in our path?

The radar's ``ObjectLateral`` is the object's centre offset from our heading
(m, left positive), ``ObjectRange`` the gap from our front to it along the
heading. The ECU does not know the object's width, so the path is widened by
a margin that covers the widest body it must protect against::

    in_path  <=>  |e| <= vehicle_width_m / 2 + path_margin_m

With our width 1.815 m (Euro NCAP's reference VUT) and ``path_margin_m`` =
1.0 m (half the ISO 19206-3 car target's 1.712 m width, plus 0.144 m for
lateral error) the corridor is ±1.91 m: every car target that overlaps our
body is in it; a car in the adjacent lane (3.5 m), a cyclist passed with
1.5 m clearance (2.66 m) or a lead car that has cut out are not. An object
outside the path triggers nothing: the planner treats it as no object.

**The path is the predicted one** (:func:`object_in_path`, issue 22), and the
prediction only clears objects from the straight corridor, never adds one: the
object must also be within the corridor about the arc the rear axle follows at
the current curvature ``kappa_0`` (:func:`ecu.core.region.paths.current_curvature`:
yaw rate over speed, below ``yaw_rate_min_speed_mps`` the wheel angle), the
stopping region's driver path. A yaw rate lags the road at a curve's entry and
leads it at its exit, so an object on the arc but off our heading is left to the
stopping region (:mod:`ecu.core.planar`, which follows the arc) rather than taken
by the line. For the point ``(x, y)`` ahead of the rear axle (``x =
rear_axle_to_front_m + range``) the signed distance from the circle of
curvature ``kappa`` through the origin, tangent to the heading, is (our
derivation; exactly ``y`` for ``kappa = 0``, ``y - kappa x^2 / 2`` to second
order)::

    e = (2 y - kappa (x^2 + y^2)) / (1 + sqrt((kappa x)^2 + (1 - kappa y)^2))

So a car parked beside a curve stays beside our path although our heading
points at it. With planar tracks, the ``RadarTrack`` nearest to the object
(:func:`nearest_track`) also gives its lateral velocity, and the object must
still be in the path when we reach it, if it is a vehicle (the DBC's size class MOTORCYCLE, CAR or TRUCK,
as :mod:`ecu.core.region.crossing`: a pedestrian or a cyclist may stop or turn within its own length,
so its held velocity predicts nothing and it stays judged where it is): its rate of approach to the arc (its
velocity over ground, ``(speed + range_rate, vy + r x_radar)``, on the arc's
normal at its station, angle ``kappa x``) held until it reaches our front
(``range / closing speed``), at most for our own shortest stop (``t_h + v /
peak_decel``: a held velocity is a guess, and a further one no longer
matters to a stop). An oncoming car in the other lane of a curve, which our
heading points at before the yaw rate has built up, thus moves out of the
path before we reach it; a car in our lane keeps its offset (no lateral
velocity relative to the arc). This is the course prediction of production
radar functions: the driving course estimated from the speed and the yaw rate
(Honda's ACC service description, "estimates the driving course based on your
vehicle speed and yaw rate"; Eaton VORAD's manual: same-lane discrimination in
curves "using host vehicle turn rate information and vehicle azimuth"), and the
other vehicle's own motion over the time to collision (path prediction for
collision avoidance, Polychronopoulos et al., IEEE T-ITS 8(3), 2007; its text
not read here). ISO 22839 / ISO 15622 were not confirmed as a source. Without
a yaw rate or planar tracks (the 1-D world) ``e`` is ``ObjectLateral`` and
nothing changes. Degraded braking (:mod:`ecu.core.degraded`) keeps the straight
corridor: while faulted the speed that turns the yaw rate into a curvature may
be the faulty input.
"""

from __future__ import annotations

import math
from typing import Sequence

from can_dbc.planar import Track

from .params import CoreParams
from .region.crossing import VEHICLE_CLASSES
from .region.paths import EgoState, current_curvature
from .types import CoreInputs


def in_path(lateral_m: float, params: CoreParams) -> bool:
    """True when an object centred ``lateral_m`` (m) off our path is in it (NaN: in it, fail-safe)."""
    return not abs(lateral_m) > params.vehicle_width_m / 2.0 + params.path_margin_m


def path_offset_m(ahead_m: float, lateral_m: float, curvature_1pm: float) -> float:
    """The signed offset (m, left positive) of the point ``(ahead_m, lateral_m)`` (rear axle frame) from the
    arc of ``curvature_1pm`` through the rear axle (module docstring); ``lateral_m`` itself when straight."""
    if curvature_1pm == 0.0:
        return lateral_m
    k, x, y = curvature_1pm, ahead_m, lateral_m
    return (2.0 * y - k * (x * x + y * y)) / (1.0 + math.sqrt((k * x) ** 2 + (1.0 - k * y) ** 2))


def nearest_track(tracks: Sequence[Track], inputs: CoreInputs, params: CoreParams) -> int | None:
    """The index of the planar track that is ``ObjectTrack``'s object: the nearest to its range and lateral
    offset, each within ``track_range_tolerance_m``; None when no track is that near."""
    tol = params.track_range_tolerance_m
    best, best_d = None, math.inf
    for i, t in enumerate(tracks):
        dx, dy = abs(t.x_m - inputs.object_range_m), abs(t.y_m - inputs.object_lateral_m)
        if dx <= tol and dy <= tol and dx + dy < best_d:
            best, best_d = i, dx + dy
    return best


def object_in_path(inputs: CoreInputs, speed_mps: float, params: CoreParams) -> bool:
    """``ObjectTrack``'s object is in the predicted path now and, with its planar track, when we reach it
    (module docstring); ``speed_mps``: our speed. Validity is not judged here."""
    region = params.region
    k = current_curvature(EgoState(speed_mps, 0.0, 0.0, inputs.yaw_rate_radps,
                                   inputs.steering_wheel_rad / params.steering_ratio), region)
    ahead = region.rear_axle_to_front_m + inputs.object_range_m
    offset = path_offset_m(ahead, inputs.object_lateral_m, k)
    if not (in_path(inputs.object_lateral_m, params) and in_path(offset, params)):
        return False
    i = nearest_track(inputs.tracks, inputs, params)
    closing = -inputs.object_range_rate_mps
    if i is None or not closing > 0.0 or inputs.tracks[i].size_class not in VEHICLE_CLASSES:
        return True
    track, angle = inputs.tracks[i], k * ahead
    ux = speed_mps + inputs.object_range_rate_mps
    uy = track.vy_mps + inputs.yaw_rate_radps * region.rear_axle_to_front_m
    horizon = min(inputs.object_range_m / closing, params.hold_time_s + speed_mps / params.peak_decel_mps2)
    return in_path(offset + (uy * math.cos(angle) - ux * math.sin(angle)) * horizon, params)
