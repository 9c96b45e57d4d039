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
from can_dbc.planar import TRACK_SLOTS, EscDynamics, Track, esc_dynamics, track
from can_dbc.units import KMH_PER_MPS, PERCENT, dbc_per_si

from .core import CoreInputs, CoreOutputs
from .core.types import NEVER_S, FaultFlag
from .equipment import CORE_INPUT_MESSAGES, PLANAR_INPUT_MESSAGES

#: every message an ECU may receive: the core's, and the planar ones (it latches them; the core does not use them
#: yet). Which of them an ECU receives is its equipment's (:mod:`ecu.equipment`)
INPUT_MESSAGES = (*CORE_INPUT_MESSAGES, *PLANAR_INPUT_MESSAGES)
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
        # the planar inputs, latched as decoded and converted only when read: the core does not use them yet
        # (the planar ECU: next issue): 1 + 8/5 frames a cycle were converted into records nobody read
        self._esc: Mapping[str, float] | None = None
        self._tracks: list[Mapping[str, float] | None] = [None] * len(TRACK_SLOTS)
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
        elif (slot := TRACK_SLOTS.get(name)) is not None:
            self._tracks[slot] = s
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
        """The latest track of each ``RadarTrack`` slot (SI), None for an empty slot or before its first frame."""
        return [None if s is None else track(s, slot) for slot, s in enumerate(self._tracks)]

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
        )


def steering_message(counter: int) -> can.Message:
    """``SteeringOverride`` pass-through (``SteerActive`` 0): the longitudinal core requests no steering (sent by
    an ECU with steering authority only, :mod:`ecu.equipment`)."""
    return encode("SteeringOverride", _NO_STEERING, counter=counter)


_NO_STEERING = {"SteerActive": 0, "SteerAngleRequest": 0.0}
_DEG_PER_RAD = dbc_per_si("deg")


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
