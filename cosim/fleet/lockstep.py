"""Several equipped vehicles in one lock-step: each a :class:`~cosim.loop.master.ClosedLoop` of its own.

Each vehicle has its own plant FMU instance, driver, ECU (in process, or ``--ecu process``: one process
each), CAN bus and record, exactly as a one-car run. What the fleet adds is the others: each car's scene
holds every other vehicle as a :class:`~cosim.fleet.bodies.PuppetMotion` object, read from one
:class:`~cosim.fleet.bodies.PoseBoard`. One ECU cycle of the fleet, at ``t = k h`` (``k`` an integer):

1. every vehicle's body is written to the board from its plant, in the fleet's order;
2. every vehicle runs the first half of its cycle (driver, radar, frames to its ECU), then every vehicle
   the second (its ECU's frames, the gateway's commands for the next cycle): each car sees the others as
   they are at ``t``, whatever the order;
3. the plants advance one cycle. When no car could touch a body within it (each car's contact watch),
   each plant takes the cycle as one ``doStep`` where it can; otherwise all plants advance one plant step
   at a time together, the board is written after each step, and each car's watch tests contact against
   the others' true poses at that step. The first contact ends the scene; every car touching a body then
   records it.

Nothing depends on wall time or on the order of the ECUs' processes: the outputs are the same in process
and with one process per ECU. A failing FMU or a stalled ECU stops the scene with the vehicle named, the
time and the cause, and every car keeps its record so far.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping

from ..errors import EcuStallError, FmiStepError, interrupt_signal, signal_name
from ..link.ecu_link import EcuOptions
from ..loop.master import ClosedLoop
from ..results.held_signals import SafePoints
from ..results.run_record import RunEvent, RunRecord
from ..world.gateway import Actuation
from .bodies import Frame, PoseBoard, PuppetMotion, vehicle_object, world_body
from .config import Fleet, Vehicle

#: (simulated time, duration) every 100 cycles
Progress = Callable[[float, float], None]


@dataclass(frozen=True)
class FleetRecord:
    """What a fleet run leaves: each vehicle's record (in the fleet's order) and the world bodies' history
    (one row per ECU cycle: t, then x, y, yaw, speed of each vehicle's box centre)."""

    fleet: Fleet
    records: tuple[RunRecord, ...]
    world_rows: list[tuple[float, ...]]

    def record(self, name: str) -> RunRecord:
        return self.records[self.fleet.names.index(name)]


class FleetRun:
    """One run of a fleet. ``strategies``: vehicle name -> strategy, overriding its ``[ecu] strategy``."""

    def __init__(self, fleet: Fleet, fmu_paths: Mapping[str, Path], strategies: Mapping[str, str] | None = None,
                 ecu: EcuOptions | None = None) -> None:
        self.fleet, self.board = fleet, PoseBoard()
        self.frames = {v.name: Frame(v.placement.x_m, v.placement.y_m, v.placement.heading_rad) for v in fleet.vehicles}
        self.loops: list[ClosedLoop] = []
        self.world_rows: list[tuple[float, ...]] = []
        try:
            for v in fleet.vehicles:
                strategy = (strategies or {}).get(v.name)
                self.loops.append(ClosedLoop(v.scenario, fmu_paths[v.name], strategy, ecu=ecu, others=self._others(v)))
        except BaseException:
            self.close()
            raise

    def _others(self, me: Vehicle) -> Callable[[int], list]:
        """The other vehicles as objects of ``me``'s scene, indexed from ``first``."""
        others = [v for v in self.fleet.vehicles if v is not me]

        def build(first: int) -> list:
            return [vehicle_object(first + j, v.name, v.scenario.plant, PuppetMotion(self.board, v.name,
                                                                                     self.frames[me.name]))
                    for j, v in enumerate(others)]
        return build

    def _post(self, t_s: float) -> None:
        """Every vehicle's body at ``t_s`` on the board (from its plant's pose now)."""
        for v, loop in zip(self.fleet.vehicles, self.loops):
            self.board.write(v.name, world_body(t_s, loop.ego_body.at(loop.plant.pose()), loop.ego_body,
                                                self.frames[v.name]))

    def _row(self, t_s: float) -> None:
        row: list[float] = [t_s]
        for v in self.fleet.vehicles:
            b = self.board.bodies[v.name].box
            row += (b.x_m, b.y_m, b.yaw_rad, b.speed_mps)
        self.world_rows.append(tuple(row))

    def _cycle(self, k: int, cycle: int, applied: list[Actuation]) -> tuple[int, list[Actuation], bool]:
        """One ECU cycle of the fleet (module docstring); the new ``k``, next commands, whether a contact ended it."""
        h, loops = self.loops[0].h_s, self.loops
        t_s = k * h
        self._post(t_s)
        self._row(t_s)
        outs = self._each(lambda i, loop: loop.cycle_out(t_s, cycle))
        nxt = self._each(lambda i, loop: loop.cycle_in(t_s, cycle, outs[i], applied[i]))
        watching = [loop.actuate(k, a, out.ego) for loop, a, out in zip(loops, applied, outs)]
        n_sub = loops[0].n_sub
        if not any(watching) and all(loop.batch_steps for loop in loops):
            self._each(lambda i, loop: loop.plant.step(t_s, n_sub * h))
            return k + n_sub, nxt, False
        for _ in range(n_sub):
            self._each(lambda i, loop: loop.plant.step(k * h, h))
            k += 1
            self._post(k * h)
            touched = [loop.touches(k) for loop, w in zip(loops, watching) if w]
            if any(touched):
                self._contact_everywhere(k)
                return k, nxt, True
        return k, nxt, False

    def _each(self, call: Callable[[int, ClosedLoop], Any]) -> list:
        """``call(i, loop)`` for every vehicle in order; an FMI error or a stalled ECU names its vehicle."""
        out = []
        for i, (v, loop) in enumerate(zip(self.fleet.vehicles, self.loops)):
            try:
                out.append(call(i, loop))
            except FmiStepError as exc:
                raise FmiStepError(f"{v.name}: {exc}", exc.time_s, exc.status) from exc
            except EcuStallError as exc:
                raise EcuStallError(f"{v.name}: {exc}", exc.time_s) from exc
        return out

    def _contact_everywhere(self, k: int) -> None:
        """After a contact: every car not yet hit tests its bodies at this step too."""
        h = self.loops[0].h_s
        for loop in self.loops:
            if not loop.record.metrics.collided:
                ego = loop.ego_body.at(loop.plant.pose())
                if loop.watch.candidates(k * h, ego, 0.0):
                    loop.touches(k)

    def run(self, progress: Progress | None = None) -> FleetRecord:
        """Run to ``[fleet] duration_s`` or the first contact; always closes every FMU, ECU and bus."""
        wall0 = time.perf_counter()
        duration_s, h = self.fleet.fleet.duration_s, self.loops[0].h_s
        total_k = int(round(duration_s / h))
        k, cycle, applied = 0, 0, [Actuation(0.0, 0.0, 0.0) for _ in self.loops]
        collided = False
        try:
            for loop in self.loops:
                loop.link.start()
            with SafePoints() as signals:
                while k < total_k and not collided:
                    k, applied, collided = self._cycle(k, cycle, applied)
                    cycle += 1
                    if progress is not None and cycle % 100 == 0:
                        progress(k * h, duration_s)
                    if signals.noted:
                        signals.act()
            if not collided:
                self._post(k * h)
                self._row(k * h)
                for loop in self.loops:
                    loop.final_sample(k * h)
        except (FmiStepError, EcuStallError) as exc:
            kind = "fmi_error" if isinstance(exc, FmiStepError) else "ecu_stalled"
            for loop in self.loops:
                loop.stop_on(exc.time_s, kind, str(exc))
        except KeyboardInterrupt as exc:
            for loop in self.loops:
                loop.record.interrupted = signal_name(interrupt_signal(exc))
                loop.record.events.append(RunEvent(k * h, "interrupted", f"{loop.record.interrupted}: stopped at "
                                                   f"t = {k * h:.3f} s, results so far kept"))
        finally:
            self.close()
        wall_s = time.perf_counter() - wall0
        for loop in self.loops:
            loop.finish(k * h, wall_s, cycle)
        return FleetRecord(self.fleet, tuple(loop.record for loop in self.loops), self.world_rows)

    def close(self) -> None:
        """Every FMU, ECU process and bus closed; safe to call twice."""
        for loop in self.loops:
            loop.close()
