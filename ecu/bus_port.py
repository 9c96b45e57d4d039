"""The codec boundary: CAN frames in DBC units <-> the core's SI records.

:class:`InputLatch` keeps the latest fresh value of each input message and the
cycle time at which it was received, and builds :class:`~ecu.core.CoreInputs`
from them. Conversions (DBC -> SI, factors from :mod:`can_dbc.units`): wheel
speeds km/h / 3.6 -> m/s, pedals % / 100 -> fraction, object range m, range rate m/s
(negative closing), lateral m,
``ObjectValid`` 0/1 -> bool. The outgoing side encodes ``SafetyOverride`` and
``EcuStatus`` through ``can_dbc.encode`` (counter and CRC filled in); status
values are clamped into their DBC ranges because they are informational. Each
:class:`~ecu.core.types.FaultFlag` bit travels as its own 1-bit ``EcuStatus``
signal (``FAULT_SIGNALS``; bit k at DBC bit 50 + k).
"""

from __future__ import annotations

import math
from typing import Mapping

import can

from can_dbc import RX_RATE, RX_SEQUENCE, Frame, Receiver, encode, signal_range
from can_dbc.contract import FAULT_SIGNALS as DBC_FAULT_SIGNALS
from can_dbc.contract import enumeration, timeout_s
from can_dbc.planar import CORNER_SLOTS, TRACK_SLOTS, EscDynamics, Track, esc_dynamics, track
from can_dbc.units import KMH_PER_MPS, PERCENT, dbc_per_si

from .core import CoreInputs, CoreOutputs
from .core.types import NEVER_S, FaultFlag
from .equipment import CORE_INPUT_MESSAGES, CORNER_INPUT_MESSAGES, PLANAR_INPUT_MESSAGES

#: every message an ECU may receive: the core's, and the planar ones (the stopping region's inputs, ecu.core.planar;
#: a track or yaw rate that is missing or stale is simply absent: the region is not evaluated). Which of them an
#: ECU receives is its equipment's (:mod:`ecu.equipment`)
INPUT_MESSAGES = (*CORE_INPUT_MESSAGES, *PLANAR_INPUT_MESSAGES, *CORNER_INPUT_MESSAGES)
SIM_CLOCK = "SimClock"
#: each fault bit's 1-bit ``EcuStatus`` signal, from the DBC (bit k at DBC bit 50 + k)
FAULT_SIGNALS: dict[FaultFlag, str] = {FaultFlag(bit): name for bit, name in enumerate(DBC_FAULT_SIGNALS)}
#: can_dbc.Receiver.rx_flags value -> the core's FaultFlag bits
_RX_FAULTS = tuple((RX_RATE & v and 1 << FaultFlag.RATE) | (RX_SEQUENCE & v and 1 << FaultFlag.SEQUENCE)
                   for v in range(4))


def fault_signals(fault_flags: int) -> dict[str, int]:
    """The ``EcuStatus`` fault signals (0/1 each) of the ``fault_flags`` bit field."""
    return {name: (fault_flags >> bit) & 1 for bit, name in FAULT_SIGNALS.items()}


def fault_flags_of(signals: Mapping[str, float]) -> int:
    """The fault bit field of a decoded ``EcuStatus`` (inverse of :func:`fault_signals`)."""
    return sum(int(signals[name]) << bit for bit, name in FAULT_SIGNALS.items())


class InputLatch:
    """Latest input values (SI) and the times (s) at which they were received."""

    def __init__(self) -> None:
        self.wheel_speeds_mps: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
        self.accel_pedal = 0.0
        self.brake_pedal = 0.0
        self.object_valid = False
        self.object_range_m = 0.0
        self.object_range_rate_mps = 0.0
        self.object_lateral_m = 0.0
        self.steering_wheel_rad = 0.0
        # the planar inputs: the yaw rate converted as it comes (one frame a cycle); the track slots latched as
        # decoded and converted once per radar report (every 5th cycle), when a slot changed
        self._esc: Mapping[str, float] | None = None
        self.yaw_rate_radps = 0.0
        self._tracks: list[Mapping[str, float] | None] = [None] * len(_SLOTS)
        self._track_tuple: tuple[Track, ...] | None = ()
        self._newest_track_t_s = NEVER_S  # the newest slot frame's receive time (no slot frame: never)
        self.rx_t_s = {name: NEVER_S for name in INPUT_MESSAGES}

    def ingest(self, frame: Frame, t_s: float) -> bool:
        """Take a fresh, checked frame received at cycle time ``t_s``; False if not an input."""
        # the three messages told apart inline, not through a dict of handler methods: one call
        # less per input frame (about two a cycle) and no bound-method look-up: a WheelSpeeds frame
        # 0.23 instead of 0.29-0.34 µs (timeit)
        name, s = frame.name, frame.signals
        if name == "WheelSpeeds":
            self.wheel_speeds_mps = (
                s["WheelSpeedFL"] / KMH_PER_MPS, s["WheelSpeedFR"] / KMH_PER_MPS,
                s["WheelSpeedRL"] / KMH_PER_MPS, s["WheelSpeedRR"] / KMH_PER_MPS,
            )
        elif name == "DriverInput":
            self.accel_pedal = s["AccelPedal"] / PERCENT
            self.brake_pedal = s["BrakePedal"] / PERCENT
            self.steering_wheel_rad = s["SteeringWheelAngle"] / _DEG_PER_RAD
        elif name == "ObjectTrack":
            self.object_valid = bool(s["ObjectValid"])
            self.object_range_m = s["ObjectRange"]
            self.object_range_rate_mps = s["ObjectRangeRate"]
            self.object_lateral_m = s["ObjectLateral"]
        elif name == "EscDynamics":
            self._esc = s
            self.yaw_rate_radps = s["YawRate"] / _DEG_PER_RAD_S
        elif (slot := _SLOTS.get(name)) is not None:
            self._tracks[slot] = s
            self._track_tuple, self._newest_track_t_s = None, t_s
        else:
            return False
        self.rx_t_s[name] = t_s
        return True

    @property
    def esc(self) -> EscDynamics | None:
        """The latest ``EscDynamics`` (SI), None before the first."""
        return None if self._esc is None else esc_dynamics(self._esc)

    @property
    def tracks(self) -> list[Track | None]:
        """The latest track of each ``RadarTrack`` slot, then each ``CornerTrack`` slot (SI), None for an empty slot
        or before its first frame (the corner slots stay None where the corner radars are not fitted)."""
        return [None if s is None else track(s, slot) for slot, s in enumerate(self._tracks)]

    def live_tracks(self, t_s: float, timeout_s: float) -> tuple[Track, ...]:
        """The tracks of the slots, empty slots left out, in slot order; none once the newest slot frame is older
        than ``timeout_s`` (a radar that fell silent reports no object)."""
        if t_s - self._newest_track_t_s > timeout_s:
            return ()
        if self._track_tuple is None:
            self._track_tuple = tuple(t for t in self.tracks if t is not None)
        return self._track_tuple

    def inputs(self, t_s: float, receiver: Receiver, node_flags: int = 0) -> CoreInputs:
        """The core's inputs at cycle time ``t_s``, with the receiver's E2E scores and rate/sequence flags."""
        rx, health = self.rx_t_s, receiver.health
        wheel_score, wheel_rx = health("WheelSpeeds", t_s)
        driver_score, driver_rx = health("DriverInput", t_s)
        object_score, object_rx = health("ObjectTrack", t_s)
        return CoreInputs(
            t_s=t_s, wheel_speeds_mps=self.wheel_speeds_mps, accel_pedal=self.accel_pedal,
            brake_pedal=self.brake_pedal, object_valid=self.object_valid, object_range_m=self.object_range_m,
            object_range_rate_mps=self.object_range_rate_mps, object_lateral_m=self.object_lateral_m,
            wheel_rx_t_s=rx["WheelSpeeds"], driver_rx_t_s=rx["DriverInput"], object_rx_t_s=rx["ObjectTrack"],
            wheel_e2e_score=wheel_score, driver_e2e_score=driver_score, object_e2e_score=object_score,
            wheel_rx_flags=_RX_FAULTS[wheel_rx], driver_rx_flags=_RX_FAULTS[driver_rx],
            object_rx_flags=_RX_FAULTS[object_rx], node_flags=node_flags,
            tracks=self.live_tracks(t_s, _TRACK_TIMEOUT_S), yaw_rate_radps=self.yaw_rate_radps,
            steering_wheel_rad=self.steering_wheel_rad,
        )


def steering_message(outputs: CoreOutputs | None, counter: int) -> can.Message:
    """``SteeringOverride`` of gated outputs (None: pass-through, ``SteerActive`` 0); sent by an ECU with steering
    authority only (:mod:`ecu.equipment`)."""
    if outputs is None or not outputs.steer_active:
        return encode("SteeringOverride", _NO_STEERING, counter=counter)
    return encode("SteeringOverride", {"SteerActive": 1, "SteerAngleRequest": outputs.steer_request_rad * _DEG_PER_RAD},
                  counter=counter)


_NO_STEERING = {"SteerActive": 0, "SteerAngleRequest": 0.0}
_DEG_PER_RAD = dbc_per_si("deg")
_DEG_PER_RAD_S = dbc_per_si("deg/s")
#: the track slots time out as ObjectTrack does (the DBC's cycle times the E2E tolerance, can_dbc.contract)
_TRACK_TIMEOUT_S = timeout_s("RadarTrack0")
#: every track slot, forward and corner: message name -> slot index
_SLOTS = {**TRACK_SLOTS, **CORNER_SLOTS}


def _clamped(value: float, limits: tuple[float, float]) -> float:
    low, high = limits
    return low if not math.isfinite(value) else min(high, max(low, value))


_PROXIMITY, _STOPPING_M, _SPEED_MPS = (signal_range("EcuStatus", name)
                                       for name in ("Proximity", "StoppingDistance", "SpeedEstimate"))


def override_message(outputs: CoreOutputs, counter: int) -> can.Message:
    """``SafetyOverride`` for gated outputs (already inside the DBC ranges)."""
    return encode("SafetyOverride", {
        "Mode": int(outputs.mode),
        "OverrideActive": int(outputs.override_active),
        "ThrottleLimit": outputs.throttle_limit_pct,
        "BrakeDecelRequest": outputs.brake_decel_request_mps2,
    }, counter=counter)


def status_message(outputs: CoreOutputs, strategy_code: int, counter: int) -> can.Message:
    """``EcuStatus``: strategy, proximity, stopping distance, speed estimate and fault flags."""
    return encode("EcuStatus", {
        "Strategy": strategy_code,
        "Proximity": _clamped(outputs.proximity, _PROXIMITY),
        "StoppingDistance": _clamped(outputs.stopping_distance_m, _STOPPING_M),
        "SpeedEstimate": _clamped(outputs.speed_estimate_mps, _SPEED_MPS),
        **fault_signals(outputs.fault_flags),
    }, counter=counter)


_REGION_RANGES = {name: signal_range("EcuRegionStatus", name)
                  for name in ("RegionProximity", "RegionCurvature", "RegionClearance", "RegionStoppingDistance")}
#: ``EcuRegionStatus.Contingency`` without planar tracks
NOT_EVALUATED = {name: value for value, name in enumeration("EcuRegionStatus", "Contingency").items()}["NOT_EVALUATED"]


def _saturated(value: float, limits: tuple[float, float]) -> float:
    """Clamped into ``limits``, +-inf to the nearer end (a clearance without objects is +inf); NaN to the low end."""
    low, high = limits
    return low if math.isnan(value) else min(high, max(low, value))


def region_message(outputs: CoreOutputs, counter: int) -> can.Message:
    """``EcuRegionStatus``: the region's contingency, proximity, curvature, clearance, stopping distance (saturated
    into their DBC ranges: informational); ``NOT_EVALUATED`` and zeros without planar tracks."""
    region = outputs.region
    if region is None:
        return encode("EcuRegionStatus", {"Contingency": NOT_EVALUATED, **dict.fromkeys(_REGION_RANGES, 0.0)},
                      counter=counter)
    values = (region.proximity, region.curvature_1pm, region.clearance_m, region.stopping_distance_m)
    return encode("EcuRegionStatus", {"Contingency": region.contingency, **{
        name: _saturated(v, limits) for (name, limits), v in zip(_REGION_RANGES.items(), values)}}, counter=counter)
