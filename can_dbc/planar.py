"""The planar frames of the contract in SI: ``EscDynamics`` and the 2-D radar tracks.

One place converts them between the DBC's units and SI, for every sender and
receiver (the co-simulation master sends them, the ECU latches them):

* :class:`EscDynamics` <-> ``EscDynamics``: yaw rate (rad/s <-> deg/s), lateral and
  longitudinal acceleration (m/s²);
* :class:`Track` <-> ``RadarTrack<slot>``: the slot's ``Track<slot>*`` signals, and the rear corner
  radars' ``CornerTrack<k>`` (slot ``8 + k``): its ``Corner<k>*`` signals;
  ``None`` is an empty slot (``Existence`` 0, ``NO_TRACK``); :func:`existence_class` maps an
  existence probability to the DBC's classes.

The slots are the DBC's ``RadarTrack*`` messages in ID order (:data:`TRACK_SLOTS`), then its
``CornerTrack*`` ones (:data:`CORNER_SLOTS`); the layout and the rule for filling them are in the
DBC's comments of ``RadarTrack0`` and ``CornerTrack0``.
Values outside a signal's DBC range are clamped into it on the way out (a sensor
saturates); the receiver refuses out-of-range raw values on the way in.
"""

from __future__ import annotations

import math
from types import MappingProxyType
from typing import Mapping, NamedTuple

from .database import LAYOUTS
from .units import dbc_per_si

_DEG_PER_RAD = dbc_per_si("deg/s")


def _slots(prefix: str, first: int) -> Mapping[str, int]:
    """``<prefix><k>`` message name -> slot index (``first + k``), in ID order."""
    names = sorted((n for n in LAYOUTS if n.startswith(prefix) and not n.endswith("Auth")),
                   key=lambda n: LAYOUTS[n].frame_id)
    return MappingProxyType({name: first + k for k, name in enumerate(names)})


#: ``RadarTrack<slot>`` message name -> slot index, in ID order: the forward radar's slots 0..7
TRACK_SLOTS: Mapping[str, int] = _slots("RadarTrack", 0)
#: ``CornerTrack<k>`` message name -> slot index, after the forward ones (8..11): the rear corner radars' slots,
#: on the bus only when they are fitted (``[radar] corner``); their PosX is signed (beside and behind the car)
CORNER_SLOTS: Mapping[str, int] = _slots("CornerTrack", len(TRACK_SLOTS))
_TRACK_FIELDS = ("Id", "SizeClass", "Existence", "PosX", "PosY", "VelX", "VelY")
#: per slot: its ``Track<slot>*`` (forward) or ``Corner<k>*`` (corner) signal names in :data:`_TRACK_FIELDS` order
_TRACK_SIGNALS = (tuple(tuple(f"Track{slot}{field}" for field in _TRACK_FIELDS) for slot in range(len(TRACK_SLOTS)))
                  + tuple(tuple(f"Corner{k}{field}" for field in _TRACK_FIELDS) for k in range(len(CORNER_SLOTS))))
_LIMITS = {(s.name): (s.minimum, s.maximum) for name in ("EscDynamics", *TRACK_SLOTS, *CORNER_SLOTS)
           for s in LAYOUTS[name].signals}
#: upper bounds (exclusive) of the existence classes 1..6 (``BELOW_25_PCT`` .. ``BELOW_99_9_PCT``); 7 is the rest
EXISTENCE_BOUNDS = (0.25, 0.50, 0.75, 0.90, 0.99, 0.999)


class EscDynamics(NamedTuple):
    """What the ESC's inertial sensor reports, in SI (ISO 8855: positive turning / accelerating left)."""

    yaw_rate_rps: float
    lat_accel_mps2: float
    long_accel_mps2: float


class Track(NamedTuple):
    """One radar track in 2-D, in SI, in the vehicle frame (x forward from the bumper, y left)."""

    track_id: int
    size_class: int
    existence: int
    x_m: float
    y_m: float
    vx_mps: float
    vy_mps: float


def existence_class(probability: float) -> int:
    """The ``Existence`` class (1..7) of an existence probability in (0, 1]; 0 (no track) for 0 or less."""
    if not probability > 0.0:
        return 0
    return 1 + next((k for k, bound in enumerate(EXISTENCE_BOUNDS) if probability < bound), len(EXISTENCE_BOUNDS))


def _clamp(name: str, value: float) -> float:
    low, high = _LIMITS[name]
    return low if not math.isfinite(value) else min(high, max(low, value))


def esc_dynamics(signals: Mapping[str, float]) -> EscDynamics:
    """The SI record of a decoded ``EscDynamics`` frame."""
    return EscDynamics(signals["YawRate"] / _DEG_PER_RAD, signals["LateralAccel"], signals["LongitudinalAccel"])


def esc_signals(esc: EscDynamics) -> dict[str, float]:
    """``EscDynamics`` signals (DBC units) of ``esc``, each clamped into its DBC range."""
    return {"YawRate": _clamp("YawRate", esc.yaw_rate_rps * _DEG_PER_RAD),
            "LateralAccel": _clamp("LateralAccel", esc.lat_accel_mps2),
            "LongitudinalAccel": _clamp("LongitudinalAccel", esc.long_accel_mps2)}


def track(signals: Mapping[str, float], slot: int) -> Track | None:
    """The track of a decoded ``RadarTrack<slot>`` frame; None for an empty slot."""
    names = _TRACK_SIGNALS[slot]
    if not signals[names[2]]:
        return None
    return Track(*(int(signals[n]) for n in names[:3]), *(signals[n] for n in names[3:]))


def track_signals(tr: Track | None, slot: int) -> dict[str, float]:
    """``RadarTrack<slot>`` signals (DBC units) of ``tr`` (None: an empty slot), clamped into range."""
    names = _TRACK_SIGNALS[slot]
    if tr is None or not tr.existence:
        return dict.fromkeys(names, 0)
    return {**dict(zip(names[:3], (tr.track_id, tr.size_class, tr.existence))),
            **{n: _clamp(n, v) for n, v in zip(names[3:], (tr.x_m, tr.y_m, tr.vx_mps, tr.vy_mps))}}
