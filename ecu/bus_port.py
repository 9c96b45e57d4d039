"""The codec boundary: CAN frames in DBC units <-> the core's SI records.

:class:`InputLatch` keeps the latest fresh value of each input message and the
cycle time at which it was received, and builds :class:`~ecu.core.CoreInputs`
from them. Conversions (DBC -> SI): wheel speeds km/h / 3.6 -> m/s, pedals
% / 100 -> fraction, object range m, range rate m/s (negative closing), lateral m,
``ObjectValid`` 0/1 -> bool. The outgoing side encodes ``SafetyOverride`` and
``EcuStatus`` through ``can_dbc.encode`` (counter and CRC filled in); status
values are clamped into their DBC ranges because they are informational. Each
:class:`~ecu.core.types.FaultFlag` bit travels as its own 1-bit ``EcuStatus``
signal (``FAULT_SIGNALS``; bit k at DBC bit 50 + k).
"""

from __future__ import annotations

import math
from typing import Callable, Mapping

import can

from can_dbc import Frame, Receiver, encode

from .core import CoreInputs, CoreOutputs
from .core.types import NEVER_S, FaultFlag

KMH_PER_MPS = 3.6
PERCENT = 100.0
#: messages the ECU consumes (the SimClock paces sim-time mode only).
INPUT_MESSAGES = ("WheelSpeeds", "DriverInput", "ObjectTrack")
SIM_CLOCK = "SimClock"
#: each fault bit's 1-bit signal in ``EcuStatus`` (the DBC places bit k at bit 50 + k)
FAULT_SIGNALS: dict[FaultFlag, str] = {
    FaultFlag.WHEEL_SPEED_TIMEOUT: "FaultWheelSpeedTimeout",
    FaultFlag.DRIVER_INPUT_TIMEOUT: "FaultDriverInputTimeout",
    FaultFlag.OBJECT_TIMEOUT: "FaultObjectTimeout",
    FaultFlag.E2E_ERROR: "FaultE2E",
    FaultFlag.INTERNAL: "FaultInternal",
}


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
        self.rx_t_s = {name: NEVER_S for name in INPUT_MESSAGES}
        self._handlers: dict[str, Callable[[dict], None]] = {
            "WheelSpeeds": self._wheels,
            "DriverInput": self._driver,
            "ObjectTrack": self._object,
        }

    def ingest(self, frame: Frame, t_s: float) -> bool:
        """Take a fresh, checked frame received at cycle time ``t_s``; False if not an input."""
        handler = self._handlers.get(frame.name)
        if handler is None:
            return False
        handler(frame.signals)
        self.rx_t_s[frame.name] = t_s
        return True

    def _wheels(self, s: dict) -> None:
        self.wheel_speeds_mps = (
            s["WheelSpeedFL"] / KMH_PER_MPS, s["WheelSpeedFR"] / KMH_PER_MPS,
            s["WheelSpeedRL"] / KMH_PER_MPS, s["WheelSpeedRR"] / KMH_PER_MPS,
        )

    def _driver(self, s: dict) -> None:
        self.accel_pedal = s["AccelPedal"] / PERCENT
        self.brake_pedal = s["BrakePedal"] / PERCENT

    def _object(self, s: dict) -> None:
        self.object_valid = bool(s["ObjectValid"])
        self.object_range_m = s["ObjectRange"]
        self.object_range_rate_mps = s["ObjectRangeRate"]
        self.object_lateral_m = s["ObjectLateral"]

    def inputs(self, t_s: float, receiver: Receiver) -> CoreInputs:
        """The core's inputs at cycle time ``t_s``, with the receiver's E2E scores."""
        rx = self.rx_t_s
        return CoreInputs(
            t_s=t_s,
            wheel_speeds_mps=self.wheel_speeds_mps,
            accel_pedal=self.accel_pedal,
            brake_pedal=self.brake_pedal,
            object_valid=self.object_valid,
            object_range_m=self.object_range_m,
            object_range_rate_mps=self.object_range_rate_mps,
            wheel_rx_t_s=rx["WheelSpeeds"],
            driver_rx_t_s=rx["DriverInput"],
            object_rx_t_s=rx["ObjectTrack"],
            wheel_e2e_score=receiver.score("WheelSpeeds"),
            driver_e2e_score=receiver.score("DriverInput"),
            object_e2e_score=receiver.score("ObjectTrack"),
            object_lateral_m=self.object_lateral_m,
        )


def _clamped(value: float, low: float, high: float) -> float:
    return low if not math.isfinite(value) else min(high, max(low, value))


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
        "Proximity": _clamped(outputs.proximity, 0.0, 1.0),
        "StoppingDistance": _clamped(outputs.stopping_distance_m, 0.0, 500.0),
        "SpeedEstimate": _clamped(outputs.speed_estimate_mps, 0.0, 100.0),
        **fault_signals(outputs.fault_flags),
    }, counter=counter)
