"""Driver intent: the acceleration the driver asks for with the pedals.

A simple documented model: the pedals map linearly to an intended
acceleration::

    a_drv = accel_pedal * driver_max_accel_mps2 - brake_pedal * peak_decel_mps2

with pedals as fractions 0..1 (a fully pressed brake pedal asks for peak
deceleration). The brake term means the ECU sees the driver's own braking
and never plans to lower it.
"""

from __future__ import annotations

from .params import CoreParams


def driver_accel_mps2(accel_pedal: float, brake_pedal: float, params: CoreParams) -> float:
    """Intended acceleration (m/s^2) from pedal fractions 0..1: ``a_drv`` above."""
    return accel_pedal * params.driver_max_accel_mps2 - brake_pedal * params.peak_decel_mps2
