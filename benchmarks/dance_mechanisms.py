"""Mechanisms for ``dance_candidates.py``: slower or later loops, brakes and radars, drivers.

Each is a drop-in for one part of the closed loop (:mod:`cosim.loop.master`),
swapped in for one experiment by :func:`patched` or :func:`every_cycle_tracks`
and restored afterwards; :func:`variant` overrides plant and ECU parameters.
None of this is used outside the benchmark.
"""

from __future__ import annotations

import contextlib
import dataclasses
from collections import deque
from types import MappingProxyType

import can_dbc.receiver as receiver
import cosim.loop.master as master
from can_dbc import ECU_CYCLE_S, LAYOUTS
from cosim.world.driver_models import Pedals
from cosim.world.gateway import Gateway
from cosim.world.radar_model import RadarModel, Track

#: the plant's brake release in the ``release`` candidates: one 10-20 ms CAN/ESC cycle of
#: signal delay and a 40 ms decay (the plant's own ABS dumps at 12 /s, three times its 4 /s
#: re-apply rate), against 0.10 s and 0.12 s for a rising command.
FAST_RELEASE = {"brake_release_dead_time_fraction": 0.2, "brake_release_time_constant_fraction": 1 / 3}


def held_gateway(n_cycles: int) -> type[Gateway]:
    """A gateway whose actuation changes only every ``n_cycles`` cycles (a slower control loop)."""

    class HeldGateway(Gateway):
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            self._k, self._held = 0, None

        def actuation(self, pedals, t_s, steering_wheel_angle_rad=0.0):
            fresh = super().actuation(pedals, t_s, steering_wheel_angle_rad)
            if self._k % n_cycles == 0 or self._held is None:
                self._held = fresh
            self._k += 1
            return self._held

    return HeldGateway


def delayed_gateway(n_cycles: int) -> type[Gateway]:
    """A gateway whose actuation reaches the plant ``n_cycles`` cycles late (a transport delay)."""

    class DelayedGateway(Gateway):
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            self._line: deque = deque()

        def actuation(self, pedals, t_s, steering_wheel_angle_rad=0.0):
            self._line.append(super().actuation(pedals, t_s, steering_wheel_angle_rad))
            return self._line.popleft() if len(self._line) > n_cycles else self._line[0]

    return DelayedGateway


def jerk_limited_gateway(jerk_mps3: float, full_decel_mps2: float = 12.0) -> type[Gateway]:
    """A gateway whose brake command rises at most ``jerk_mps3`` (m/s^3 at the gateway's default
    ``brake_full_decel_mps2`` = 12 m/s^2 for a command of 1) and falls at once."""
    step = jerk_mps3 * ECU_CYCLE_S / full_decel_mps2

    class JerkLimitedGateway(Gateway):
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            self._brake = 0.0

        def actuation(self, pedals, t_s, steering_wheel_angle_rad=0.0):
            fresh = super().actuation(pedals, t_s, steering_wheel_angle_rad)
            self._brake = min(fresh.brake, self._brake + step)
            return fresh._replace(brake=self._brake)

    return JerkLimitedGateway


def tracked_radar(alpha: float = 0.5, hold_updates: int = 1) -> type[RadarModel]:
    """A radar that reports an alpha-beta tracked range, each track held for ``hold_updates`` updates.

    Constant-velocity alpha-beta filter at the track period T (Benedict and Bordner 1962; the
    critically damped pair ``beta = alpha^2 / (2 - alpha)``)::

        r_p = r + T * rdot;  e = z - r_p;  r = r_p + alpha * e;  rdot = rdot + beta / T * e

    ``hold_updates`` = 2 makes a 10 Hz perception node out of the DBC's 20 Hz track."""
    beta, period_s = alpha * alpha / (2.0 - alpha), LAYOUTS["ObjectTrack"].cycle_time_ms / 1000.0

    class TrackedRadar(RadarModel):
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            self._r: float | None = None
            self._rdot, self._k, self._out = 0.0, 0, None

        def measure(self) -> Track:
            z = super().measure()
            if not z.valid:
                self._r = None
            elif self._r is None:
                self._r, self._rdot = z.range_m, z.range_rate_mps
            else:
                predicted = self._r + period_s * self._rdot
                err = z.range_m - predicted
                self._r, self._rdot = predicted + alpha * err, self._rdot + beta / period_s * err
            fresh = z if self._r is None else Track(True, max(0.0, self._r), self._rdot, z.lateral_m)
            if self._k % hold_updates == 0 or self._out is None:
                self._out = fresh
            self._k += 1
            return self._out

    return TrackedRadar


class ReactingDriver:
    """Full throttle, lifted after ``reaction_s`` of unrequested braking, re-applied after ``reaction_s`` without."""

    def __init__(self, accel_pct: float, reaction_s: float, perceive_mps2: float = 2.0) -> None:
        self.accel_pct, self.reaction_s, self.perceive_mps2 = accel_pct, reaction_s, perceive_mps2
        self._v: float | None = None
        self._lifted, self._since_s = False, 0.0

    def __call__(self, t_s: float, position_m: float, speed_mps: float) -> Pedals:
        braking = self._v is not None and (speed_mps - self._v) / ECU_CYCLE_S < -self.perceive_mps2
        self._v = speed_mps
        self._since_s = self._since_s + ECU_CYCLE_S if braking != self._lifted else 0.0
        if self._since_s >= self.reaction_s - 1e-9:
            self._lifted, self._since_s = not self._lifted, 0.0
        return Pedals(0.0 if self._lifted else self.accel_pct, 0.0)


@contextlib.contextmanager
def every_cycle_tracks():
    """``ObjectTrack`` every 10 ms; the receivers' rate monitors expect it (an experiment only)."""
    init, monitor = master.ClosedLoop.__init__, receiver.RateMonitor

    def patched_init(self, *args, **kwargs):
        init(self, *args, **kwargs)
        self.n_track = 1

    master.ClosedLoop.__init__ = patched_init
    track_s = LAYOUTS["ObjectTrack"].cycle_time_ms / 1000.0  # only ObjectTrack changes its rate
    receiver.RateMonitor = lambda cycle_s: monitor(ECU_CYCLE_S if cycle_s == track_s else cycle_s)
    try:
        yield
    finally:
        master.ClosedLoop.__init__, receiver.RateMonitor = init, monitor


@contextlib.contextmanager
def patched(gateway_cls=Gateway, reaction_s: float | None = None, radar_cls=RadarModel):
    """Run with another gateway and radar class and, given ``reaction_s``, the reacting driver."""
    make = master.make_driver
    master.Gateway, master.RadarModel = gateway_cls, radar_cls
    if reaction_s is not None:
        master.make_driver = lambda cfg, seed=0: ReactingDriver(cfg.accel_pedal_pct, reaction_s)
    try:
        yield
    finally:
        master.Gateway, master.make_driver, master.RadarModel = Gateway, make, RadarModel


def variant(base, ecu=None, plant=None, radar_latency_s=None):
    """``base`` with ECU and plant parameters overridden and, optionally, another radar latency."""
    sc = base
    if ecu:
        sc = dataclasses.replace(sc, ecu=dataclasses.replace(sc.ecu, **ecu))
    if plant:
        sc = dataclasses.replace(sc, plant=dataclasses.replace(
            sc.plant, parameters=MappingProxyType(dict(sc.plant.parameters) | plant)))
    if radar_latency_s is not None:
        sc = dataclasses.replace(sc, radar=dataclasses.replace(sc.radar, latency_s=radar_latency_s))
    return sc


#: the CARLA-like plant: no brake dead time, a 20 ms pressure lag, a 50 ms drive-force lag.
NO_LAG = {"brake_dead_time": 0.0, "brake_time_constant": 0.02, "throttle_time_constant": 0.05}
