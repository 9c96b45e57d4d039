"""The rear corner radars (``[radar] corner = true``): cars beside and behind the ego, as ``CornerTrack0..3``.

Production cars carry a radar in each rear corner for blind-spot monitoring and lane-change assist
(ISO 17387, *Lane change decision aid systems (LCDAS)*, specifies the zones beside and behind the car
such a system covers; its figures are not quoted here, none is used). The forward radar sees nothing
beside the car (``RadarTrack``'s x is 0..250 m), so two cars side by side know nothing of each other
until they touch (``crd fleet merge``). This module is the world's model of the two corner sensors.

**Sensors**: two :mod:`cosim.world.radar2d` radars, one at each rear corner of the ego's box
(``x`` at the rear bumper, ``y = +-width/2``), bore sight ``CORNER_BORESIGHT_DEG`` (110 degrees) off the
ego's heading toward its side, field of view ``CORNER_FIELD_OF_VIEW_DEG`` (150 degrees, so each sees
from 35 degrees off the heading on its side round to 5 degrees past the centre line behind), range
``CORNER_MAX_RANGE_M`` (80 m). The angles and the range are assumptions (unconfirmed: not taken from
a data sheet), chosen so that the two sensors and the forward radar (+-45 degrees from the bumper)
leave no gap beside the car: a car in the next lane level with our front half, which the forward radar
does not see (its near corner 2.6 m to the side and 2 m ahead is 52 degrees off), is 15 to 60 degrees
off the rear corner's sensor (``crd fleet merge`` with the ramp 2 m behind lost it at 135 degrees). Latency, noise, dropouts, period and
seed are the ``[radar]`` table's, as for the forward radar (:mod:`cosim.world.radar_tracks`); each
sensor draws from its own generator (seed ``seed + 1`` and ``seed + 2``; the front ones ``seed + 3`` and ``+ 4``).

**Which point**: every track is reported in the forward radar's frame (x from the front bumper's
centre, forward; y left) at the point of the object's box nearest that origin, with the velocity
relative to it: the point from which the ECU places a box (:mod:`ecu.core.region.objects`), so a car
beside the ego (x < 0) is placed as a car ahead is.

**Front corners** (``[radar] front_corner = true``): two more sensors, at the front corners, bore sight
``FRONT_BORESIGHT_DEG`` (70 degrees) off the heading toward their side, the same 150-degree field and 80 m
(no further than the forward radar's ``max_range_m``: a scenario that uncovers an object by that range
uncovers it to them too). A target on a collision course keeps its bearing, ``atan(v_target / v_ego)``
for one crossing at right angles: 56 degrees for a cyclist at 15 km/h and an ego at 10 km/h, 74 for a car
at 70 km/h and an ego at 20, both outside the forward radar's +-45 (the cells of ``ncap_vru`` and
``ncap_junction`` whose target it never sees). Production cars that brake for crossing traffic carry front
corner radars or wide cameras for this; the angles are the rear sensors' turned forward, assumptions as
theirs. Their tracks join the forward radar's in one list (:class:`FrontFeed`, the ``RadarTrack`` slots:
a fused front object list, by the same rule as below, eight slots).

**Which tracks** (the slot rule of ``CornerTrack0``'s DBC comment): every object either sensor sees,
once (seen by both: the report of the sensor with the higher existence, then the lower id of the
sensor, left first), most urgent first in the forward radar's order (ascending time to collision,
range, id), at most ``len(CORNER_SLOTS)`` (4). An object both the forward and a corner radar see
appears in both lists: the ECU's region is a union of objects, so a duplicate changes nothing.
"""

from __future__ import annotations

import math
from dataclasses import replace

from can_dbc.planar import CORNER_SLOTS

from .ego import Ego, EgoBody
from .radar2d import Radar2DParams, RadarMount, Track
from .radar_tracks import TrackFeed
from .scene import Scene

CORNER_BORESIGHT_DEG = 110.0
FRONT_BORESIGHT_DEG = 70.0
CORNER_FIELD_OF_VIEW_DEG = 150.0
CORNER_MAX_RANGE_M = 80.0


def corner_params(forward: Radar2DParams, ego: EgoBody, front: bool = False) -> tuple[Radar2DParams, Radar2DParams]:
    """The left and right corner sensors' parameters, from the forward radar's (``[radar]``; module docstring): at
    the rear corners, or (``front``) at the front ones, seeded ``seed + 3`` and ``seed + 4``."""
    half_w = ego.half_width_m
    x_m, bore, first, slots, reach = (ego.front_m - ego.length_m, CORNER_BORESIGHT_DEG, 1, len(CORNER_SLOTS),
                                      CORNER_MAX_RANGE_M)
    if front:
        x_m, bore, first, slots = ego.front_m, FRONT_BORESIGHT_DEG, 3, forward.max_tracks
        reach = min(reach, forward.max_range_m)
    origin = RadarMount(x_m=ego.front_m)
    return tuple(replace(forward, mount=RadarMount(x_m, side * half_w, side * math.radians(bore)),
                         field_of_view_deg=CORNER_FIELD_OF_VIEW_DEG, max_range_m=reach,
                         max_tracks=slots, seed=forward.seed + first + k, report_at=origin)
                 for k, side in ((0, 1.0), (1, -1.0)))


def merged(lists: tuple[tuple[Track, ...], ...], slots: int) -> tuple[Track, ...]:
    """One list of several sensors' tracks (module docstring: which tracks)."""
    best: dict[int, Track] = {}
    for track in (t for tracks in lists for t in tracks):
        if track.id not in best or track.existence > best[track.id].existence:
            best[track.id] = track
    return tuple(sorted(best.values(), key=lambda t: (t.ttc_s, t.range_m, t.id))[:slots])


class CornerFeed:
    """Both corner sensors on the scene; the merged tracks on report cycles (None on the others)."""

    def __init__(self, scene: Scene, forward: Radar2DParams, ego: EgoBody) -> None:
        self.sensors = tuple(TrackFeed(scene, params) for params in corner_params(forward, ego))

    def step(self, cycle: int, t_s: float, ego: Ego) -> tuple[Track, ...] | None:
        """The merged tracks of this cycle (call it on every ECU cycle, as :meth:`TrackFeed.step`)."""
        scan = self.sensors[0].scan(cycle, t_s, ego)  # one scan of the scene for both (same period and latency)
        left, right = (sensor.report(scan) for sensor in self.sensors)
        if left is None or right is None:
            return None
        return merged((left, right), len(CORNER_SLOTS))


class FrontFeed:
    """The forward radar and the two front corner sensors; their tracks in one list on report cycles (module
    docstring: front corners), as a :class:`~cosim.world.radar_tracks.TrackFeed` gives the forward radar's."""

    def __init__(self, scene: Scene, forward: Radar2DParams, ego: EgoBody) -> None:
        self.forward = TrackFeed(scene, forward)
        self.sensors = tuple(TrackFeed(scene, params) for params in corner_params(forward, ego, front=True))
        self.slots = forward.max_tracks

    def step(self, cycle: int, t_s: float, ego: Ego) -> tuple[Track, ...] | None:
        """The fused tracks of this cycle (call it on every ECU cycle)."""
        scan = self.forward.scan(cycle, t_s, ego)  # one scan of the scene for the three (same period and latency)
        lists = tuple(feed.report(scan) for feed in (self.forward, *self.sensors))
        return None if any(tracks is None for tracks in lists) else merged(lists, self.slots)  # type: ignore[arg-type]


def forward_feed(scene: Scene, forward: Radar2DParams, ego: EgoBody, front_corner: bool) -> TrackFeed | FrontFeed:
    """The feed of the ``RadarTrack`` slots: the forward radar's, with the front corners' when fitted."""
    return FrontFeed(scene, forward, ego) if front_corner else TrackFeed(scene, forward)
