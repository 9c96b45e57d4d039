"""Where a cycle's time goes, measured only when asked (``profile=True``).

:func:`instrument` replaces a closed loop's collaborators (plant, link, the
node's step, the gateway, the driver and radar models, the frame encoding and
the logging) with timed stand-ins that charge their *own* time (minus that of
timed calls nested inside them) to one phase each. The loop itself has no
profiling branches: an uninstrumented run calls the real objects directly.

Phases: ``fmu`` (every FMU call), ``codec`` (encoding the master's frames,
the gateway's checks), ``bus`` (moving frames), ``ecu`` (the in-process
node's cycle), ``logging`` (the run record), ``models`` (driver, steering and radar), ``world`` (the
scene: objects, gaps, the radar's object, contact, the 2-D radar's tracks).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any, Callable

from ..link.in_process import InProcessLink

if TYPE_CHECKING:
    from .master import ClosedLoop

PHASES = ("fmu", "codec", "bus", "ecu", "logging", "models", "world")


class PhaseTimer:
    """Exclusive wall time (ns) per phase: nested timed calls are charged to their own phase."""

    def __init__(self) -> None:
        self.ns = dict.fromkeys(PHASES, 0)
        self._nested: list[int] = []  # per open timed call: time spent in timed calls inside it

    def timed(self, phase: str, fn: Callable) -> Callable:
        ns, nested, clock = self.ns, self._nested, time.perf_counter_ns

        def call(*args: Any, **kwargs: Any) -> Any:
            t0 = clock()
            nested.append(0)
            try:
                return fn(*args, **kwargs)
            finally:
                spent = clock() - t0
                ns[phase] += spent - nested.pop()
                if nested:
                    nested[-1] += spent
        return call

    def per_cycle_s(self, cycles: int) -> dict[str, float]:
        return {phase: spent / cycles / 1e9 for phase, spent in self.ns.items()}


class Timed:
    """``target`` with the methods named in ``phases`` timed; every other attribute passes through."""

    def __init__(self, target: Any, timer: PhaseTimer, phases: dict[str, str]) -> None:
        self._target = target
        for name, phase in phases.items():
            setattr(self, name, timer.timed(phase, getattr(target, name)))

    def __getattr__(self, name: str) -> Any:
        return getattr(self._target, name)


def instrument(loop: "ClosedLoop") -> PhaseTimer:
    """Time ``loop``'s phases from now on; returns the timer."""
    timer = PhaseTimer()
    loop.plant = Timed(loop.plant, timer, {m: "fmu" for m in ("read", "step", "set_actuation", "pose")})
    if isinstance(loop.link, InProcessLink):
        loop.link.time_phases(timer.timed)
    loop.link = Timed(loop.link, timer, {"send": "bus", "collect": "bus", "pace": "bus"})
    loop.gateway = Timed(loop.gateway, timer, {"offer": "codec", "actuation": "codec"})
    loop.driver = timer.timed("models", loop.driver)
    loop.radar = Timed(loop.radar, timer, {"sample": "models", "measure": "models"})
    loop._frames_out = timer.timed("codec", loop._frames_out)
    loop._log_cycle = timer.timed("logging", loop._log_cycle)
    loop.scene = Timed(loop.scene, timer, {"observe": "world", "radar_truth": "world", "end_reason": "world",
                                           "path_gap": "world"})
    loop.watch = Timed(loop.watch, timer, {"candidates": "world", "contact": "world"})
    if loop.steering is not None:
        loop.steering = timer.timed("models", loop.steering)
    if loop.tracks is not None:
        loop.tracks = Timed(loop.tracks, timer, {"step": "world"})
    return timer
