"""The planar frames the co-simulation master sends: ``EscDynamics``, ``RadarTrack0..7`` and ``CornerTrack0..3``.

* ``EscDynamics`` every ECU cycle (10 ms), from the plant's motion (:class:`can_dbc.planar.EscDynamics`).
* ``RadarTrack<slot>`` every radar cycle (50 ms), each slot with its own E2E counter: the
  radar's tracks in its report order, slot 0 first, the slots beyond them sent empty, tracks
  beyond the eighth not sent (the slot rule in the DBC);
* ``CornerTrack<k>`` on the same cycles where the rear corner radars are fitted (``[radar] corner``): their
  merged tracks (:mod:`cosim.world.corner_radar`) by the same rule, four slots.

Both are sent only to an ECU equipped with the planar sensors (a planar scene, :mod:`ecu.equipment`):
a 1-D run's bus carries neither.
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import can

from can_dbc import ECU_CYCLE_S, LAYOUTS, CounterSequence, FrameError, check_alone, encode, signal_layout
from can_dbc.contract import enumeration
from can_dbc.planar import CORNER_SLOTS, TRACK_SLOTS, EscDynamics, Track, esc_signals, track_signals

from ..world.radar2d import Track as Radar2DTrack

_EXISTENCE = {name: v for v, name in enumeration("RadarTrack0", "Track0Existence").items()}
_SIZE = {name: v for v, name in enumeration("RadarTrack0", "Track0SizeClass").items()}
_WHEEL_ANGLE_MAX_DEG = signal_layout("DriverInput", "SteeringWheelAngle").maximum
_WHEEL_RATE_MAX_DEGPS = signal_layout("DriverInput", "SteeringWheelRate").maximum


#: existence probability -> the DBC's existence class: the first class whose upper bound is not below it
_EXISTENCE_BOUNDS = ((0.25, "BELOW_25_PCT"), (0.5, "BELOW_50_PCT"), (0.75, "BELOW_75_PCT"), (0.9, "BELOW_90_PCT"),
                     (0.99, "BELOW_99_PCT"), (0.999, "BELOW_99_9_PCT"))


def existence_class(p: float) -> int:
    """The ``Track<i>Existence`` value of an existence probability ``p`` (0 < p <= 1)."""
    return _EXISTENCE[next((name for bound, name in _EXISTENCE_BOUNDS if p < bound), "UP_TO_100_PCT")]


def tracks_2d(tracks: Sequence[Radar2DTrack]) -> list[Track]:
    """The 2-D radar's tracks (:mod:`cosim.world.radar2d`, in its report order) as the contract's tracks; the
    size class by name (the targets' classes are the DBC's, lower case), unknown names as ``UNKNOWN``."""
    return [Track(t.id, _SIZE.get(t.size_class.upper(), _SIZE["UNKNOWN"]), existence_class(t.existence),
                  t.x_m, t.y_m, t.vx_mps, t.vy_mps) for t in tracks if t.existence > 0.0]


class PlanarFrames:
    """Encodes the planar frames with one E2E counter per message."""

    def __init__(self) -> None:
        self._next_esc = CounterSequence().next
        self._next_slot = tuple(CounterSequence().next for _ in (*TRACK_SLOTS, *CORNER_SLOTS))
        self._wheel_deg = 0.0  # the steering-wheel angle last sent (deg), for its rate

    def steering_wheel(self, steering_rad: float) -> dict[str, float]:
        """``DriverInput``'s steering signals (DBC units) for the driver's wheel angle this cycle: the angle,
        and its rate as the difference to the last cycle's over the ECU cycle, each clamped into range."""
        deg = min(_WHEEL_ANGLE_MAX_DEG, max(-_WHEEL_ANGLE_MAX_DEG, math.degrees(steering_rad)))
        rate = min(_WHEEL_RATE_MAX_DEGPS, max(-_WHEEL_RATE_MAX_DEGPS, (deg - self._wheel_deg) / ECU_CYCLE_S))
        self._wheel_deg = deg
        return {"SteeringWheelAngle": deg, "SteeringWheelRate": rate}

    def esc_of(self, yaw_rate_radps: float, ay_mps2: float, ax_mps2: float) -> can.Message:
        """``EscDynamics`` from the plant's motion in the vehicle frame (PlantSample: its ay and ax outputs, or
        vx * yaw rate and its accel without them)."""
        return self.esc(EscDynamics(yaw_rate_radps, ay_mps2, ax_mps2))

    def esc(self, esc: EscDynamics) -> can.Message:
        """``EscDynamics`` of this cycle."""
        return encode("EscDynamics", esc_signals(esc), self._next_esc())

    def tracks(self, tracks: Sequence[Track]) -> list[can.Message]:
        """The eight ``RadarTrack`` slots of this radar cycle: ``tracks`` in order, then empty slots."""
        return self._slots(tracks, TRACK_SLOTS)

    def corner_tracks(self, tracks: Sequence[Track]) -> list[can.Message]:
        """The four ``CornerTrack`` slots of this radar cycle: ``tracks`` in order, then empty slots."""
        return self._slots(tracks, CORNER_SLOTS)

    def _slots(self, tracks: Sequence[Track], slots: Mapping[str, int]) -> list[can.Message]:
        first = min(slots.values())
        return [encode(name, track_signals(tracks[slot - first] if slot - first < len(tracks) else None, slot),
                       self._next_slot[slot]()) for name, slot in slots.items()]


_REGION_ID = LAYOUTS["EcuRegionStatus"].frame_id
_REGION_SIGNALS = ("Contingency", "RegionProximity", "RegionCurvature", "RegionClearance", "RegionStoppingDistance")


class RegionCells:
    """The time series' region cells (``REGION_COLUMNS`` but the overlay): the last ``EcuRegionStatus`` the ECU
    sent, each frame checked on its own (CRC; a bad one is skipped), NaN before the first."""

    def __init__(self) -> None:
        self._cells: tuple[float, ...] = (math.nan,) * len(_REGION_SIGNALS)

    def cells(self, received: Sequence[can.Message]) -> tuple[float, ...]:
        """The cells after this cycle's frames from the ECU."""
        for msg in received:
            if msg.arbitration_id == _REGION_ID:
                try:
                    signals = check_alone(msg).signals
                except FrameError:
                    continue
                self._cells = tuple(float(signals[name]) for name in _REGION_SIGNALS)
        return self._cells
