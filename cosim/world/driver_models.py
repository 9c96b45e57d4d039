"""Driver models: the guidance task of selective determinism, as pedal positions.

Each model maps the vehicle's state at an ECU cycle boundary to pedals in
percent (the ``DriverInput`` units). They disregard the object on purpose:
the paper's driver is "asleep at the wheel or distracted by a cell phone".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..scenarios.config import DriverConfig


@dataclass(frozen=True, slots=True)
class Pedals:
    """Pedal positions in percent (0..100)."""

    accel_pct: float
    brake_pct: float


DriverModel = Callable[[float, float, float], Pedals]
"""``model(t_s, position_m, speed_mps) -> Pedals``."""


def full_throttle(cfg: DriverConfig) -> DriverModel:
    """Accelerator held at ``cfg.accel_pedal_pct`` whatever happens (the paper's driver)."""
    pedals = Pedals(cfg.accel_pedal_pct, 0.0)
    return lambda t_s, position_m, speed_mps: pedals


def cruise(cfg: DriverConfig) -> DriverModel:
    """Hold ``set_speed_mps`` with a proportional law.

    ``u = gain_pct_per_mps * (set_speed_mps - v)``; ``u > 0`` is accelerator,
    ``u < 0`` is brake, each clipped to 0..100 %.
    """

    def model(t_s: float, position_m: float, speed_mps: float) -> Pedals:
        u = cfg.gain_pct_per_mps * (cfg.set_speed_mps - speed_mps)
        return Pedals(min(100.0, max(0.0, u)), min(100.0, max(0.0, -u)))

    return model


def scripted(cfg: DriverConfig) -> DriverModel:
    """Pedals interpolated linearly from the breakpoint table ``cfg.points``.

    The abscissa is time (s) or position (m) per ``cfg.over``; values are held
    beyond the first and last breakpoints. An empty table means no pedals.
    """
    if not cfg.points:
        return lambda t_s, position_m, speed_mps: Pedals(0.0, 0.0)
    table = np.asarray(cfg.points, dtype=float)
    at, acc, brk = table[:, 0], table[:, 1], table[:, 2]
    by_time = cfg.over == "time"

    def model(t_s: float, position_m: float, speed_mps: float) -> Pedals:
        s = t_s if by_time else position_m
        return Pedals(float(np.interp(s, at, acc)), float(np.interp(s, at, brk)))

    return model


DRIVER_MODELS: dict[str, Callable[[DriverConfig], DriverModel]] = {
    "full_throttle": full_throttle,
    "cruise": cruise,
    "scripted": scripted,
}


def make_driver(cfg: DriverConfig) -> DriverModel:
    """The driver model named by ``cfg.model``."""
    return DRIVER_MODELS[cfg.model](cfg)
