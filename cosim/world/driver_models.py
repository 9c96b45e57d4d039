"""Driver models: the guidance task of selective determinism, as pedal positions.

Each model maps the vehicle's state at an ECU cycle boundary to pedals in
percent (the ``DriverInput`` units). They disregard the object on purpose:
the paper's driver is "asleep at the wheel or distracted by a cell phone".
The wheel is the steering model's (:mod:`cosim.world.steering_models`).
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from typing import Callable

import numpy as np

from can_dbc import ECU_CYCLE_S

from ..scenarios.config import DriverConfig


@dataclass(frozen=True, slots=True)
class Pedals:
    """Pedal positions in percent (0..100)."""

    accel_pct: float
    brake_pct: float


DriverModel = Callable[[float, float, float], Pedals]
"""``model(t_s, position_m, speed_mps) -> Pedals``."""


def full_throttle(cfg: DriverConfig, seed: int = 0) -> DriverModel:
    """Accelerator held at ``cfg.accel_pedal_pct`` whatever happens; without ``[driver.steering]`` the wheel is
    held straight too: the paper's distracted driver, "asleep at the wheel or distracted by a cell phone"."""
    pedals = Pedals(cfg.accel_pedal_pct, 0.0)
    return lambda t_s, position_m, speed_mps: pedals


def cruise(cfg: DriverConfig, seed: int = 0) -> DriverModel:
    """Hold ``set_speed_mps`` with a proportional law.

    ``u = gain_pct_per_mps * (set_speed_mps - v)``; ``u > 0`` is accelerator,
    ``u < 0`` is brake, each clipped to 0..100 %.
    """

    def model(t_s: float, position_m: float, speed_mps: float) -> Pedals:
        u = cfg.gain_pct_per_mps * (cfg.set_speed_mps - speed_mps)
        return Pedals(min(100.0, max(0.0, u)), min(100.0, max(0.0, -u)))

    return model


def hold_speed(cfg: DriverConfig, seed: int = 0, cycle_s: float = ECU_CYCLE_S) -> DriverModel:
    """A test robot holding ``set_speed_mps``: PI on speed, accelerator only.

    ``e = set_speed_mps - v``; ``I += e * cycle_s`` while the accelerator is not
    saturated (conditional integration, no wind-up);
    ``accel% = clip(gain_pct_per_mps * e + integral_gain_pct_per_m * I, 0, 100)``.
    The integral removes the steady-state error of a P law (the road load needs
    a non-zero pedal at zero error). It never brakes (a test robot does not
    override the system under test). With ``release_drop_mps > 0`` it lifts off
    the accelerator for the rest of the run once ``v < set_speed_mps -
    release_drop_mps``: the Euro NCAP robot releases the pedal once the speed
    has dropped by 5 km/h (Euro NCAP 2026 Crash Avoidance - Frontal Collisions
    v1.1, test conditions). Called once per ECU cycle of ``cycle_s``.
    """
    kp, ki = cfg.gain_pct_per_mps, cfg.integral_gain_pct_per_m
    state = {"integral": 0.0, "released": False}

    def model(t_s: float, position_m: float, speed_mps: float) -> Pedals:
        error = cfg.set_speed_mps - speed_mps
        if cfg.release_drop_mps > 0.0 and error > cfg.release_drop_mps:
            state["released"] = True
        if state["released"]:
            return Pedals(0.0, 0.0)
        u = kp * error + ki * state["integral"]
        if 0.0 < u < 100.0 or (u >= 100.0 and error < 0.0) or (u <= 0.0 and error > 0.0):
            state["integral"] += error * cycle_s
        return Pedals(min(100.0, max(0.0, u)), 0.0)

    return model


def scripted(cfg: DriverConfig, seed: int = 0) -> DriverModel:
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


def reacting(cfg: DriverConfig, seed: int = 0) -> DriverModel:
    """The paper's full-throttle driver, with a human's reaction time: he lifts off when he feels the
    car brake by itself, and presses the accelerator again once it has stopped braking.

    He holds ``accel_pedal_pct`` until the car decelerates harder than ``felt_decel_mps2`` (the
    deceleration over the last ECU cycle, from the speed he sees); one reaction time later he lifts
    off (a reaction once begun is carried out). Once the car no longer decelerates that hard, he
    presses again one reaction time later (if it brakes again meanwhile, he waits for it to end). Each reaction time is drawn uniformly from
    ``reaction_time_min_s`` to ``reaction_time_max_s`` (Green 2000, "How long does it take to stop?",
    Transportation Human Factors 2(3): 0.70-0.75 s for a fully expected signal, about 1.25 s for an
    unexpected but common one, about 1.5 s for a surprise), by a generator seeded with
    ``[scenario] seed``. Called once per ECU cycle, in order.
    """
    rng = random.Random(f"reacting driver/{seed}")
    state = {"v_mps": None, "pressed": True, "due_s": None}
    pressing, lifted = Pedals(cfg.accel_pedal_pct, 0.0), Pedals(0.0, 0.0)

    def model(t_s: float, position_m: float, speed_mps: float) -> Pedals:
        previous, state["v_mps"] = state["v_mps"], speed_mps
        braking = previous is not None and (previous - speed_mps) / ECU_CYCLE_S > cfg.felt_decel_mps2
        if braking != (not state["pressed"]):  # what he does and what he feels disagree: he will react
            if state["due_s"] is None:
                state["due_s"] = t_s + rng.uniform(cfg.reaction_time_min_s, cfg.reaction_time_max_s)
        elif not state["pressed"]:
            state["due_s"] = None  # lifted, and it brakes again: he waits for it to end
        if state["due_s"] is not None and t_s >= state["due_s"]:
            state["pressed"], state["due_s"] = not state["pressed"], None
        return pressing if state["pressed"] else lifted

    return model


#: ``factory(cfg, seed)``: every model takes the run's seed; those that draw nothing at random ignore it
DRIVER_MODELS: dict[str, Callable[[DriverConfig, int], DriverModel]] = {
    "full_throttle": full_throttle,
    "cruise": cruise,
    "scripted": scripted,
    "hold_speed": hold_speed,
    "reacting": reacting,
}


def make_driver(cfg: DriverConfig, seed: int = 0) -> DriverModel:
    """The driver model named by ``cfg.model``; a model that draws at random is seeded with ``seed``."""
    return DRIVER_MODELS[cfg.model](cfg, seed)
