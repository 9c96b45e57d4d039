"""A narrowing ahead and who passes it first (issue 23): the traffic-law way out of ``crd fleet narrow_passage``.

German road traffic law, StVO section 6 (Vorbeifahren): "Wer an einer Fahrbahnverengung, einem Hindernis auf
der Fahrbahn oder einem haltenden Fahrzeug vorbeifahren will, muss entgegenkommende Fahrzeuge durchfahren
lassen." (whoever wants to pass a narrowing of the carriageway, an obstacle on it or a stopped vehicle must let
oncoming vehicles through; quoted from memory of the current wording, not checked against the official text
here). Two equipped cars that meet head-on in a one-lane passage otherwise both stop inside it, face to face,
and neither can back up (the plant does not reverse).

**Perception** (:func:`find_narrowing`), from the tracks alone (the contract carries no map):

* a *pair*: a standing track (speed over ground within the region's ``moving_object_speed_mps``) ahead on our
  left and one on our right whose spans along our heading overlap (each from its nearest point on, its class's
  length long), leaving a free width (left nearest point's ``y`` minus right's) below the room two cars need,
  ``2 (vehicle_width_m + 2 (lateral_margin_m + sigma_factor sigma))``: each car as the stopping region sees it
  (its footprint with the RSS margin, the other's box inflated by 3 sigma), so two cars that met in it would
  both find their stopping paths touching. With our parameters 6.07 m;
* the narrowing: the nearest pair and the pairs that follow it with gaps shorter than two of our lengths (too
  short to pull into without reversing; argued, not sourced); its *entry* the nearest pair's near end, its
  *exit* the last pair's far end, both along our heading from the front bumper;
* the obstacle is *ours* when a right-hand object reaches into our lane (``y > -lane_width_m / 2``: we must leave
  our lane to pass it) and *theirs* when a left-hand one reaches into the lane left of ours (``y < 1.5
  lane_width_m``, the lane the ECU assumes for oncoming traffic), each ``y`` taken along the passage (less the
  drift of its centre line, :func:`in_corridor`, since our bumper), so that a car steering toward the gap
  judges as one aligned with the road.

**Who goes first** (:func:`must_yield`), against each oncoming vehicle (vehicle class, moving, its velocity over
ground within 30 degrees of our opposite heading, within a lane of the passage's centre line (:func:`in_corridor`), its rear not yet past our
entry: in the narrowing or coming toward it). Each car's speed held (both judged alike; a standing car reaches
nothing): we reach the entry at ``t_in`` and our waiting line (below) at ``t_wait``; it enters at ``t_them_in``
(0 when already in: its nearest point short of the exit) and has left our end at ``t_them_out`` (its nearest
point plus its class's length past our entry). We yield when it is still in the narrowing when we would reach
our waiting line (``t_them_out > t_wait``: a car that would get there later slows only as much as it must) and,
if the obstacle is theirs too (both must let the other through: the symmetric passage), when it enters first
(``t_them_in <= t_in + TIE_S``, :data:`TIE_S`); with the obstacle ours alone, when it enters before we have left
(``t_them_in < t_out``). Already in the narrowing (its entry at or behind our bumper) we never yield. In the
exact tie both yield and slow.

**Standoff** (:func:`standoff`): at a two-sided narrowing, once both wait (slow, below
``way_out_slow_speed_mps``), neither sees the other coming and so neither would yield: both would go at once and
meet in the middle. So a car slow before a two-sided narrowing also waits while a standing vehicle waits on the
other side (:func:`waiting_partner`), and that wait, not the one for a car on the move, is what the seeded
patience of :mod:`ecu.core.way_out` counts. The car whose patience runs out first takes its turn; the other sees
it come, yields to a car on the move, and its patience starts again. Two draws closer than the time to see the
other start (its speed over ``moving_object_speed_mps``, a radar latency later: about 0.4 s) both go; each then
sees the other on the move toward the narrowing while taking its turn (:class:`Turn`, *contested*), and both
back off: they yield to any car on the move, stop again, and wait a fresh seeded draw of their patience
(:mod:`ecu.core.way_out`), so that one goes first.

**Yielding** (:func:`narrowing_proximity`): the car must stop *before* the narrowing, ``narrowing_wait_m``
short of its entry, where the oncoming car, leaving it in the middle of the road, can get back to its own side
before it passes us. The proximity is that of the nominal stopping path (speed, the bounded command held for
``t_h``, then the model deceleration, :mod:`ecu.core.stopping_path`) to that line, and the strategy's
``tighten`` turns it into the bound, as for crossing vehicles (:mod:`ecu.core.region.crossing`). Only the bound:
the contingency keeps our stopping path disjoint from every object's region as always.
"""

from __future__ import annotations

import math
from enum import IntEnum
from types import MappingProxyType
from typing import Callable, Mapping, NamedTuple, Sequence

from ..params import CoreParams
from ..stopping_path import stopping_distance_m
from .crossing import CROSSING_ANGLE_RAD, VEHICLE_CLASSES
from .decision import proximity_of
from .objects import TrackBox
from .params import CAPABILITIES
from .paths import EgoState


#: arrivals at the narrowing closer than this are a tie, and both cars yield (the patience then decides): each
#: car sees the other a radar latency late (0.1 s) and the far end a class length's error off (4.0 m for a
#: parked car of 4.5 m: 0.06 s at 30 km/h), so both would otherwise claim to be first; five times that
TIE_S = 0.5


class Narrowing(NamedTuple):
    """A narrowing ahead (module docstring): entry and exit along our heading from the front bumper (m), its
    least free width (m), whether the obstacle is ours and theirs, and its centre line (the free gap's centre
    at the entry, ``y`` m, and its slope, m per m along our heading: :func:`in_corridor`)."""

    entry_m: float
    exit_m: float
    width_m: float
    ours: bool
    theirs: bool
    centre_y_m: float
    centre_slope: float


def _length_m(track: TrackBox) -> float:
    return CAPABILITIES.get(track.size_class, CAPABILITIES[0]).length_m


def room_for_two_m(params: CoreParams) -> float:
    """The free width two cars need to meet (module docstring)."""
    region = params.region
    return 2.0 * (params.vehicle_width_m + 2.0 * (region.lateral_margin_m
                                                  + region.sigma_factor * params.track_position_sigma_m))


def _standing_ahead(tracks: Sequence[TrackBox], speed_mps: float, params: CoreParams) -> list[TrackBox]:
    limit = params.region.moving_object_speed_mps
    return [t for t in tracks if t.x_m > 0.0 and math.hypot(t.vx_mps + speed_mps, t.vy_mps) <= limit]


def _pairs(standing: Sequence[TrackBox], params: CoreParams) -> list[tuple[float, float, float, float, float]]:
    """(near end, far end, free width, right y, left y) of every pair narrower than the room for two."""
    room = room_for_two_m(params)
    pairs = []
    for left in (t for t in standing if t.y_m > 0.0):
        for right in (t for t in standing if t.y_m < 0.0):
            near, far = max(left.x_m, right.x_m), min(left.x_m + _length_m(left), right.x_m + _length_m(right))
            if near < far and left.y_m - right.y_m < room:
                pairs.append((min(left.x_m, right.x_m), far, left.y_m - right.y_m, right.y_m, left.y_m))
    return sorted(pairs)


def find_narrowing(tracks: Sequence[TrackBox], speed_mps: float, params: CoreParams) -> Narrowing | None:
    """The narrowing ahead of the module docstring; None without one."""
    pairs = _pairs(_standing_ahead(tracks, speed_mps, params), params)
    if not pairs:
        return None
    entry, exit_m, width = pairs[0][0], pairs[0][1], pairs[0][2]
    included = [pairs[0]]
    for pair in pairs[1:]:
        if pair[0] > exit_m + 2.0 * params.region.length_m:
            break
        exit_m, width = max(exit_m, pair[1]), min(width, pair[2])
        included.append(pair)
    first, last = included[0], included[-1]
    centre, run_m = 0.5 * (first[3] + first[4]), last[0] - entry
    slope = (0.5 * (last[3] + last[4]) - centre) / run_m if run_m >= params.region.length_m else 0.0
    # lanes are judged along the passage: an offset less the centre line's drift since our bumper
    ours = any(r - slope * near > -0.5 * params.lane_width_m for near, _, _, r, _ in included)
    theirs = any(l_ - slope * near < 1.5 * params.lane_width_m for near, _, _, _, l_ in included)
    return Narrowing(entry, exit_m, width, ours, theirs, centre, slope)


def in_corridor(track: TrackBox, narrowing: Narrowing, params: CoreParams) -> bool:
    """The track lies within a lane's width of the narrowing's centre line (:class:`Narrowing`), the line through
    the free gap's centre at its first and last pair (along our heading with one pair, or pairs closer than our
    length): where a vehicle that comes through the gap, or waits for it, drives. Measured along the passage, not
    our heading: a car steering toward the gap sees the far end of the passage, and a car waiting beyond it,
    several metres to one side (``crd fleet narrow_passage_tie``: 5 m at 37 m with our heading 8 degrees off)."""
    centre = narrowing.centre_y_m + narrowing.centre_slope * (track.x_m - narrowing.entry_m)
    return abs(track.y_m - centre) <= params.lane_width_m


def time_to_m(distance_m: float, speed_mps: float) -> float:
    """Time (s) to cover ``distance_m`` at ``speed_mps`` held: 0 when there, inf when standing short of it."""
    if distance_m <= 0.0:
        return 0.0
    return distance_m / speed_mps if speed_mps > 0.0 else math.inf


def _oncoming(track: TrackBox, speed_mps: float, narrowing: Narrowing, params: CoreParams) -> float:
    """The track's speed toward us over ground (m/s) if it is an oncoming vehicle not yet out of the narrowing
    at our end (its rear beyond our entry), else 0."""
    ux, uy = track.vx_mps + speed_mps, track.vy_mps
    lanes = in_corridor(track, narrowing, params)
    toward = ux < -params.region.moving_object_speed_mps and abs(uy) <= -ux * math.tan(CROSSING_ANGLE_RAD)
    ok = track.size_class in VEHICLE_CLASSES and lanes and toward and track.x_m + _length_m(track) > narrowing.entry_m
    return -ux if ok else 0.0


def waiting_partner(track: TrackBox, speed_mps: float, narrowing: Narrowing, params: CoreParams) -> bool:
    """A standing vehicle within a lane of the passage's centre line (:func:`in_corridor`), beyond the narrowing's far end and within two waiting
    distances of it: the other car of a two-sided narrowing, waiting on its side (module docstring, Standoff)."""
    standing = math.hypot(track.vx_mps + speed_mps, track.vy_mps) <= params.region.moving_object_speed_mps
    lanes = in_corridor(track, narrowing, params)
    beyond = narrowing.exit_m <= track.x_m <= narrowing.exit_m + 2.0 * params.narrowing_wait_m
    return track.size_class in VEHICLE_CLASSES and standing and lanes and beyond


def standoff(narrowing: Narrowing, tracks: Sequence[TrackBox], ego: EgoState, params: CoreParams) -> bool:
    """Both sides must let the other through, we wait, and so does a car on the other side: neither has the right
    to go, and only the patience of :mod:`ecu.core.way_out` can part them (module docstring, Standoff)."""
    if not (narrowing.ours and narrowing.theirs) or ego.speed_mps >= params.way_out_slow_speed_mps:
        return False
    return any(waiting_partner(t, ego.speed_mps, narrowing, params) for t in tracks)


def must_yield(narrowing: Narrowing, tracks: Sequence[TrackBox], ego: EgoState, params: CoreParams) -> bool:
    """Whether we let an oncoming vehicle through the narrowing first (module docstring)."""
    if not narrowing.ours or narrowing.entry_m <= 0.0:
        return False
    v = ego.speed_mps
    t_in = time_to_m(narrowing.entry_m, v)
    t_out = time_to_m(narrowing.exit_m + params.region.length_m, v)
    t_wait = time_to_m(narrowing.entry_m - params.narrowing_wait_m, v)
    for track in tracks:
        u = _oncoming(track, v, narrowing, params)
        if u <= 0.0:
            continue
        them_in = max(0.0, track.x_m - narrowing.exit_m) / u
        them_out = (track.x_m + _length_m(track) - narrowing.entry_m) / u
        first = them_in <= t_in + TIE_S if narrowing.theirs else them_in < t_out
        if first and them_out > t_wait:
            return True
    return False


class Turn(IntEnum):
    """Where a car stands in the way-out patience of :mod:`ecu.core.way_out` at a narrowing."""

    #: approaching, or waiting its patience out
    NONE = 0
    #: impatient: it takes its turn, past a standoff (yet it yields to a car that has taken it too)
    TAKING = 1
    #: it took its turn with another car and gave it back: it yields to any car on the move toward the narrowing
    BACKED_OFF = 2


class AtNarrowing(NamedTuple):
    """A narrowing rule's answer: the proximity to tighten by toward the waiting line; whether the car waits in a
    standoff (what the way-out patience counts, :func:`ecu.core.planar.held_back`); whether a car taking or
    having given back its turn meets a vehicle on the move toward the narrowing (*contested*: both took their
    turn at once, :mod:`ecu.core.way_out` backs off); whether a narrowing lies ahead at all."""

    proximity: float
    standoff: bool
    contested: bool = False
    found: bool = False


NOT_AT_ONE = AtNarrowing(0.0, False)


def _stvo_6(tracks: Sequence[TrackBox], ego: EgoState, params: CoreParams, turn: Turn) -> AtNarrowing:
    narrowing = find_narrowing(tracks, ego.speed_mps, params)
    if narrowing is None or narrowing.entry_m <= 0.0:
        return NOT_AT_ONE
    waiting = turn != Turn.TAKING and standoff(narrowing, tracks, ego, params)
    contested = turn != Turn.NONE and any(_oncoming(t, ego.speed_mps, narrowing, params) > 0.0 for t in tracks)
    if not (waiting or contested or must_yield(narrowing, tracks, ego, params)):
        return AtNarrowing(0.0, False, False, True)
    stop = stopping_distance_m(ego.speed_mps, ego.accel_mps2, params.hold_time_s, ego.decel_mps2)
    proximity = proximity_of(narrowing.entry_m - params.narrowing_wait_m - stop, params.region)
    return AtNarrowing(proximity, waiting, contested, True)


def _never(tracks: Sequence[TrackBox], ego: EgoState, params: CoreParams, turn: Turn) -> AtNarrowing:
    return NOT_AT_ONE


#: a narrowing rule: (the tracks, the ego, the parameters, the car's turn) -> its answer (:class:`AtNarrowing`)
NarrowingRule = Callable[[Sequence[TrackBox], EgoState, CoreParams, Turn], AtNarrowing]
#: ``[ecu] way_out`` -> its rule at a narrowing (the keys of :data:`ecu.core.region.crossing.WAY_OUT_RULES`)
NARROWING_RULES: Mapping[str, NarrowingRule] = MappingProxyType({
    "none": _never,               # the plain method
    "right_of_way": _stvo_6,      # let oncoming traffic through a narrowing (StVO section 6)
    "reciprocal": _never,         # ORCA's split has no rule of the road
})
