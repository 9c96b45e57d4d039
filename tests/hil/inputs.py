"""Input frames of a driving situation, in DBC units, for the HIL tests."""

from __future__ import annotations

from can_dbc.units import KMH_PER_MPS

from .harness import Harness

#: start-up: FAULT until the inputs have been valid for the recovery cycles (10), plus margin.
STARTUP_S = 0.3


def wheels(speed_mps: float) -> dict:
    kmh = speed_mps * KMH_PER_MPS
    return {"WheelSpeedFL": kmh, "WheelSpeedFR": kmh, "WheelSpeedRL": kmh, "WheelSpeedRR": kmh}


def driver(accel_pct: float = 100.0, brake_pct: float = 0.0) -> dict:
    return {"AccelPedal": accel_pct, "BrakePedal": brake_pct, "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}


def obj(range_m: float | None, range_rate_mps: float = 0.0) -> dict:
    if range_m is None:
        return {"ObjectValid": 0, "ObjectRange": 0.0, "ObjectRangeRate": 0.0, "ObjectLateral": 0.0}
    return {"ObjectValid": 1, "ObjectRange": range_m, "ObjectRangeRate": range_rate_mps,
            "ObjectLateral": 0.0}


def drive(h: Harness, speed_mps: float, accel_pct: float = 100.0, range_m: float | None = None) -> None:
    """Periodic inputs at their DBC cycle times: a car at constant speed, a stationary object."""
    h.periodic("WheelSpeeds", wheels(speed_mps), 0.01)
    h.periodic("DriverInput", driver(accel_pct), 0.01)
    h.periodic("ObjectTrack", obj(range_m, -speed_mps), 0.05)


def in_standby(h: Harness) -> None:
    h.expect("SafetyOverride", {"Mode": 0}, timeout_s=STARTUP_S)
