"""The co-simulation master: fixed-step lock-step of plant FMU, CAN bus and ECU.

Time is ``t = k * h`` from an integer step counter ``k`` (plant step ``h``,
default 1 ms); the ECU cycle is ``N = 0.01 / h`` plant steps. At each cycle
boundary, in this order:

1. read the plant outputs; the driver model makes the pedals;
2. send ``DriverInput`` and ``WheelSpeeds`` (every cycle) and ``ObjectTrack``
   (every 5th cycle), each with its own E2E counter, on an in-process python-can
   virtual bus with a channel unique to the run;
3. ``EcuNode.step(t)`` (the ECU drains those frames and sends ``SafetyOverride``);
4. the gateway drains the ECU's frames and computes the plant commands, which
   take effect from the NEXT cycle on (the natural one-cycle latency);
5. the plant advances N steps with the commands computed one cycle earlier.

Every frame is logged with the simulation time as its time stamp (the virtual
bus stamps wall time, so the log keeps its own copies). Collision: the front
bumper reaches the object's rear; the run stops at that plant step and records
the relative impact speed. Between cycles the position is read only when a
collision is possible within the cycle, which keeps the run deterministic and
cheap.
"""

from __future__ import annotations

import itertools
import logging
import os
import time
from pathlib import Path
from typing import Callable

import can
import numpy as np

from can_dbc import CounterSequence, encode
from ecu import EcuConfig, EcuNode

from .driver_models import make_driver
from .errors import FmiStepError
from .gateway import Actuation, Gateway
from .plant_fmu import FmuPlant, PlantSample
from .radar_model import RadarModel
from .run_record import LoggedFrame, RunEvent, RunMetrics, RunRecord
from .scenario_config import ECU_CYCLE_S, OBJECT_TRACK_PERIOD_S, Scenario
from .scene_objects import LaneObject

log = logging.getLogger(__name__)

_channels = itertools.count()
_KMH_PER_MPS = 3.6
_WHEEL_MAX_KMH = 400.0  # DBC range of WheelSpeedXX
_ACCEL_BOUND_MPS2 = 50.0  # no plant moves faster than this within a cycle: bounds the collision look-ahead
PHASES = ("fmu", "codec", "bus", "ecu", "logging", "models")

Progress = Callable[[float, float], None]


def ecu_config(scenario: Scenario, strategy: str | None = None) -> EcuConfig:
    """The scenario's ``[ecu]`` as an :class:`ecu.EcuConfig` (``strategy`` overrides)."""
    params = dict(scenario.ecu.parameters)
    params["strategy"] = strategy or scenario.ecu.strategy
    return EcuConfig.from_dict(params, where="ecu")


class ClosedLoop:
    """One run of one strategy. Build, then :meth:`run`; the FMU and buses are closed after."""

    def __init__(self, scenario: Scenario, fmu_path: Path, strategy: str | None = None,
                 profile: bool = False) -> None:
        self.sc = scenario
        self.strategy = strategy or scenario.ecu.strategy
        self._ecu_cfg = ecu_config(scenario, self.strategy)
        self.h_s = scenario.scenario.step_s
        self.n_sub = int(round(ECU_CYCLE_S / self.h_s))
        self.n_track = int(round(OBJECT_TRACK_PERIOD_S / ECU_CYCLE_S))
        self.obj = LaneObject.from_config(scenario.object)
        self.driver = make_driver(scenario.driver)
        self.radar = RadarModel(scenario.radar, np.random.default_rng(scenario.scenario.seed))
        self.gateway = Gateway(scenario.gateway)
        self.record = RunRecord(self.strategy, RunMetrics(self.strategy))
        self._seq = {name: CounterSequence() for name in ("DriverInput", "WheelSpeeds", "ObjectTrack")}
        self._cost = dict.fromkeys(PHASES, 0) if profile else None
        self.plant = FmuPlant(scenario.plant, fmu_path)
        self.record.fmu_path, self.record.fmu_sha256 = str(fmu_path), self.plant.sha256
        channel = f"crd-{os.getpid()}-{next(_channels)}"
        self._bus = can.Bus(interface="virtual", channel=channel, receive_own_messages=False)
        self._ecu_bus = can.Bus(interface="virtual", channel=channel, receive_own_messages=False)
        self.node = EcuNode(self._ecu_bus, self._ecu_cfg)

    # -- one cycle ------------------------------------------------------------
    def _frames_out(self, t_s: float, cycle: int, sample: PlantSample, pedals, gap_m) -> list:
        wheels = [min(_WHEEL_MAX_KMH, max(0.0, w * _KMH_PER_MPS)) for w in sample.wheel_speeds_mps]
        out = [
            encode("DriverInput", {"AccelPedal": pedals.accel_pct, "BrakePedal": pedals.brake_pct,
                                   "SteeringWheelAngle": 0.0}, self._seq["DriverInput"].next()),
            encode("WheelSpeeds", dict(zip(("WheelSpeedFL", "WheelSpeedFR", "WheelSpeedRL", "WheelSpeedRR"),
                                           wheels)), self._seq["WheelSpeeds"].next()),
        ]
        if cycle % self.n_track == 0:
            out.append(encode("ObjectTrack", self.radar.measure().signals(), self._seq["ObjectTrack"].next()))
        return out

    def _cycle(self, t_s: float, cycle: int, applied: Actuation) -> tuple[Actuation, float]:
        clock, cost = time.perf_counter_ns, self._cost
        c0 = clock() if cost is not None else 0
        sample = self.plant.read()
        c1 = clock() if cost is not None else 0
        bumper_m = sample.position_m + self.sc.plant.front_bumper_offset_m
        gap_m = self.obj.gap_m(t_s, bumper_m) if self.obj else float("inf")
        pedals = self.driver(t_s, sample.position_m, sample.speed_mps)
        if self.obj:
            self.radar.sample(gap_m, self.obj.speed_mps - sample.speed_mps, self.obj.lateral_m)
        else:
            self.radar.sample(None, 0.0)
        c2 = clock() if cost is not None else 0
        frames = self._frames_out(t_s, cycle, sample, pedals, gap_m)
        c3 = clock() if cost is not None else 0
        for msg in frames:
            self._bus.send(msg)
        c4 = clock() if cost is not None else 0
        self.node.step(t_s)
        c5 = clock() if cost is not None else 0
        received = []
        while (msg := self._bus.recv(timeout=0.0)) is not None:
            received.append(msg)
        c6 = clock() if cost is not None else 0
        for msg in received:
            self.gateway.offer(msg, t_s)
        nxt = self.gateway.actuation(pedals, t_s)
        c7 = clock() if cost is not None else 0
        log_frames = self.record.frames
        for msg in itertools.chain(frames, received):
            log_frames.append(LoggedFrame(t_s, msg.arbitration_id, bytes(msg.data)))
        self.record.rows.append((t_s, sample.position_m, sample.speed_mps, sample.accel_mps2, applied.throttle,
                                 applied.brake, self.gateway.mode, gap_m, pedals.accel_pct, pedals.brake_pct))
        if cost is not None:
            c8 = clock()
            cost["fmu"] += c1 - c0
            cost["models"] += c2 - c1
            cost["codec"] += (c3 - c2) + (c7 - c6)
            cost["bus"] += (c4 - c3) + (c6 - c5)
            cost["ecu"] += c5 - c4
            cost["logging"] += c8 - c7
        return nxt, gap_m

    def _advance(self, k: int, applied: Actuation, gap_m: float, speed_mps: float) -> tuple[int, bool]:
        """Advance the plant one ECU cycle; returns the new ``k`` and whether it collided."""
        c0 = time.perf_counter_ns() if self._cost is not None else 0
        plant, h = self.plant, self.h_s
        plant.set_actuation(applied.throttle, applied.brake)
        span = self.n_sub * h
        closing = speed_mps - (self.obj.speed_mps if self.obj else 0.0)
        watch = self.obj is not None and gap_m <= max(closing, 0.0) * span + 0.5 * _ACCEL_BOUND_MPS2 * span**2 + 0.01
        collided = False
        for _ in range(self.n_sub):
            plant.step(k * h, h)
            k += 1
            if watch:
                pos, v = plant.position_speed()
                gap = self.obj.gap_m(k * h, pos + self.sc.plant.front_bumper_offset_m)
                if gap <= 0.0:
                    self._collide(k * h, gap, v)
                    collided = True
                    break
        if self._cost is not None:
            self._cost["fmu"] += time.perf_counter_ns() - c0
        return k, collided

    def _collide(self, t_s: float, gap_m: float, speed_mps: float) -> None:
        m = self.record.metrics
        m.collided = True
        m.impact_speed_mps = speed_mps - self.obj.speed_mps
        m.min_gap_m = gap_m if m.min_gap_m is None else min(m.min_gap_m, gap_m)
        self.record.events.append(RunEvent(t_s, "collision", f"relative impact speed {m.impact_speed_mps:.3f} m/s"))
        log.info("%s: collision at t=%.3f s, %.2f m/s", self.strategy, t_s, m.impact_speed_mps)

    # -- the run -----------------------------------------------------------------
    def run(self, progress: Progress | None = None) -> RunRecord:
        """Run to the scenario's duration, a collision or an FMI error; always closes the FMU and buses."""
        wall0 = time.perf_counter()
        duration_s = self.sc.scenario.duration_s
        total_k = int(round(duration_s / self.h_s))
        k, cycle, applied = 0, 0, Actuation(0.0, 0.0)
        try:
            while k < total_k:
                t_s = k * self.h_s
                nxt, gap_m = self._cycle(t_s, cycle, applied)
                self._track(gap_m)
                k, collided = self._advance(k, applied, gap_m, self.record.rows[-1][2])
                applied, cycle = nxt, cycle + 1
                if progress is not None and cycle % 100 == 0:
                    progress(k * self.h_s, duration_s)
                if collided:
                    break
            if not self.record.metrics.collided:
                self._final(k * self.h_s)
        except FmiStepError as exc:
            self.record.error = str(exc)
            self.record.events.append(RunEvent(exc.time_s, "fmi_error", str(exc)))
            log.error("%s: %s", self.strategy, exc)
        finally:
            self.close()
        self._finish(k * self.h_s, time.perf_counter() - wall0, cycle)
        return self.record

    def _track(self, gap_m: float) -> None:
        m = self.record.metrics
        m.min_gap_m = gap_m if m.min_gap_m is None else min(m.min_gap_m, gap_m)
        m.max_speed_mps = max(m.max_speed_mps, self.record.rows[-1][2])

    def _final(self, t_s: float) -> None:
        """Final sample at the end of the run (outputs after the last step)."""
        sample = self.plant.read()
        gap = self.obj.gap_m(t_s, sample.position_m + self.sc.plant.front_bumper_offset_m) if self.obj else None
        m = self.record.metrics
        m.final_gap_m = gap
        if gap is not None:
            m.min_gap_m = min(m.min_gap_m, gap) if m.min_gap_m is not None else gap
        m.max_speed_mps = max(m.max_speed_mps, sample.speed_mps)

    def _finish(self, t_s: float, wall_s: float, cycles: int) -> None:
        m = self.record.metrics
        m.sim_time_s = t_s
        m.wall_time_s = wall_s
        m.contingency_invocations = self.gateway.contingency_invocations
        if m.min_gap_m is not None and not np.isfinite(m.min_gap_m):
            m.min_gap_m = None
        self.record.events[:0] = [RunEvent(e.t_s, e.kind, e.detail) for e in self.gateway.events]
        self.record.events.sort(key=lambda e: e.t_s)
        if self._cost is not None and cycles:
            self.record.cycle_cost_s = {k: v / cycles / 1e9 for k, v in self._cost.items()}

    def close(self) -> None:
        """Free the FMU and shut both bus ends down; safe to call twice."""
        self.plant.close()
        self._ecu_bus.shutdown()
        self._bus.shutdown()


def run_scenario(scenario: Scenario, fmu_path: Path, strategy: str | None = None,
                 progress: Progress | None = None, profile: bool = False) -> RunRecord:
    """Build and run one closed loop; see :class:`ClosedLoop`."""
    return ClosedLoop(scenario, fmu_path, strategy, profile).run(progress)
