"""The planar frames the co-simulation master sends: ``EscDynamics`` and ``ObjectTrack2D_0..7``.

* ``EscDynamics`` every ECU cycle (10 ms), from the plant: its longitudinal acceleration
  (the ``accel`` output). Yaw rate and lateral acceleration are the plant's ``yaw_rate``
  and ``ay`` once the plant wrapper reads them (issue 21, part 3); until then they are sent
  as 0, which is what the planar plant gives while nothing steers it (today's drivers hold
  the wheel straight and the ECU requests no steering).
* ``ObjectTrack2D_<slot>`` every radar cycle (50 ms), each slot with its own E2E counter:
  today's radar model measures one object, which goes to slot 0 in 2-D (x = range,
  y = lateral offset, vx = range rate, vy = 0, size class ``UNKNOWN``: the model has no
  class; id 0); the other slots are sent empty. The 2-D radar (part 3) fills them,
  nearest first (the slot rule in the DBC).
"""

from __future__ import annotations

import can

from can_dbc import CounterSequence, encode
from can_dbc.contract import enumeration
from can_dbc.planar import TRACK_SLOTS, EscDynamics, Track, esc_signals, track_signals

from ..world.plant_fmu import PlantSample
from ..world.radar_model import Track as RadarTrack

#: ``Existence`` of a track the radar model reports (its dropout is drawn separately)
_EXISTING = next(v for v, name in enumeration("ObjectTrack2D_0", "Track0Existence").items()
                 if name == "UP_TO_100_PCT")
_UNKNOWN_SIZE = next(v for v, name in enumeration("ObjectTrack2D_0", "Track0SizeClass").items() if name == "UNKNOWN")


class PlanarFrames:
    """Encodes the planar frames with one E2E counter per message."""

    def __init__(self) -> None:
        self._next_esc = CounterSequence().next
        self._next_slot = tuple(CounterSequence().next for _ in TRACK_SLOTS)

    def esc(self, sample: PlantSample) -> can.Message:
        """``EscDynamics`` of this cycle's plant sample."""
        return encode("EscDynamics", esc_signals(EscDynamics(0.0, 0.0, sample.accel_mps2)), self._next_esc())

    def tracks(self, measured: RadarTrack) -> list[can.Message]:
        """The eight ``ObjectTrack2D`` slots of this radar cycle (slot 0: the measured object, if any)."""
        tracks: list[Track | None] = [None] * len(TRACK_SLOTS)
        if measured.valid:
            tracks[0] = Track(0, _UNKNOWN_SIZE, _EXISTING, measured.range_m, measured.lateral_m,
                              measured.range_rate_mps, 0.0)
        return [encode(name, track_signals(tracks[slot], slot), self._next_slot[slot]())
                for name, slot in TRACK_SLOTS.items()]
