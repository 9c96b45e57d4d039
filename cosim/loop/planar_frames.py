"""The planar frames the co-simulation master sends: ``EscDynamics`` and ``RadarTrack0..7``.

* ``EscDynamics`` every ECU cycle (10 ms), from the plant's motion (:class:`can_dbc.planar.EscDynamics`).
* ``RadarTrack<slot>`` every radar cycle (50 ms), each slot with its own E2E counter: the
  radar's tracks in its report order, slot 0 first, the slots beyond them sent empty, tracks
  beyond the eighth not sent (the slot rule in the DBC). :func:`tracks_of` turns today's 1-D
  radar measurement into that list: one track, the measured object in 2-D (x = range,
  y = lateral offset, vx = range rate, vy = 0; id 0; size class ``UNKNOWN``: the model has none;
  existence the top class: the model reports an object or none).
"""

from __future__ import annotations

from typing import Sequence

import can

from can_dbc import CounterSequence, encode
from can_dbc.contract import enumeration
from can_dbc.planar import TRACK_SLOTS, EscDynamics, Track, esc_signals, track_signals

from ..world.radar_model import Track as RadarTrack

_EXISTENCE = {name: v for v, name in enumeration("RadarTrack0", "Track0Existence").items()}
_SIZE = {name: v for v, name in enumeration("RadarTrack0", "Track0SizeClass").items()}


def tracks_of(measured: RadarTrack) -> list[Track]:
    """Today's radar measurement as a list of 2-D tracks (empty when it reports no object)."""
    if not measured.valid:
        return []
    return [Track(0, _SIZE["UNKNOWN"], _EXISTENCE["UP_TO_100_PCT"], measured.range_m, measured.lateral_m,
                  measured.range_rate_mps, 0.0)]


class PlanarFrames:
    """Encodes the planar frames with one E2E counter per message."""

    def __init__(self) -> None:
        self._next_esc = CounterSequence().next
        self._next_slot = tuple(CounterSequence().next for _ in TRACK_SLOTS)

    def esc(self, esc: EscDynamics) -> can.Message:
        """``EscDynamics`` of this cycle."""
        return encode("EscDynamics", esc_signals(esc), self._next_esc())

    def tracks(self, tracks: Sequence[Track]) -> list[can.Message]:
        """The eight ``RadarTrack`` slots of this radar cycle: ``tracks`` in order, then empty slots."""
        return [encode(name, track_signals(tracks[slot] if slot < len(tracks) else None, slot),
                       self._next_slot[slot]()) for name, slot in TRACK_SLOTS.items()]
