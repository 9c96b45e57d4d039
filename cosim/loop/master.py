"""The co-simulation master: fixed-step lock-step of plant FMU, CAN bus and ECU.

Time is ``t = k * h`` from an integer step counter ``k`` (plant step ``h``,
default 1 ms); the ECU cycle is ``N = c / h`` plant steps, with ``c`` the DBC's
10 ms cycle (:data:`can_dbc.ECU_CYCLE_S`). At each cycle
boundary, in this order:

1. read the plant outputs; the driver model makes the pedals;
2. send ``DriverInput`` and ``WheelSpeeds`` (every cycle) and ``ObjectTrack`` (every 5th cycle;
   to an ECU with the planar sensors, :mod:`ecu.equipment`, also ``EscDynamics`` and ``RadarTrack0..7``),
   each with its own E2E counter, to the ECU through the
   link chosen by :class:`cosim.link.ecu_link.EcuOptions` (an
   :class:`~cosim.link.ecu_link.EcuLink`): by default an in-process bus with
   a channel unique to the run, or a bus shared with a ``crd ecu`` process
   (then followed by ``SimClock``);
3. the ECU runs one cycle (``EcuNode.step(t)`` in process, or the ECU
   process's cycle on that ``SimClock``) and sends ``SafetyOverride``;
4. the gateway takes the ECU's frames (an ECU process: waiting, bounded, for
   them) and computes the plant commands, which take effect from the NEXT
   cycle on (the natural one-cycle latency);
5. the plant advances N steps with the commands computed one cycle earlier.
   An FMU that declares an FMI 3 ``fixedInternalStepSize`` dividing ``h``
   (and variable communication steps) gets them as ONE ``doStep`` of N·h:
   its integrator takes the same internal steps either way and the inputs
   are constant within the cycle, so the trajectory is the same (bit for
   bit for our plant: ``tests/cosim/test_step_batching.py``). Any other FMU,
   and every cycle in which a collision is possible, is stepped h at a time.
   (Overlapping this with the ECU process's cycle was measured slower on 2
   cores: the hub thread then contends for the GIL with the FMU stepping.)

Every frame is logged with the simulation time as its time stamp (a bus may
stamp wall time, so the log keeps its own copies). Profiling (``profile=True``)
wraps the collaborators in timers (:mod:`cosim.loop.phase_timer`); the loop
itself has no profiling branches. Collision: the front
bumper reaches the object's rear; the run stops at that plant step and records
the relative impact speed. Between cycles the position is read only when a
collision is possible within the cycle, which keeps the run deterministic and
cheap.

How a run ends (``RunRecord.status``): ``ok`` at its duration, ``collided``,
``error`` (the FMU failed or gave a NaN/Inf output, checked once per cycle on
what the master reads; or, in lock-step, the ECU stalled past
``stall_timeout_s``: :mod:`cosim.link.stall`), or ``interrupted`` (SIGINT, or
SIGTERM via :mod:`cosim.cli.signals`). In every case the record keeps all
cycles up to the stop, and the FMU, an ECU process and the bus are closed.
Events from the link, the gateway and the loop are merged rate-limited
(:func:`cosim.results.events.merge_events`).
"""

from __future__ import annotations

import logging
import math
import time
from pathlib import Path
from typing import Callable

from numpy.random import default_rng  # here, not at the first run: each forked run worker would import it

from can_dbc import ECU_CYCLE_S, CounterSequence, SecOcSender, encode, signal_layout
from can_dbc.units import KMH_PER_MPS
from ecu.equipment import EQUIPMENT

from ..errors import EcuStallError, FmiStepError, interrupt_signal, signal_name
from ..link.ecu_link import EcuOptions, open_link, run_key
from ..results.events import merge_events
from ..results.held_signals import SafePoints
from ..results.run_record import LoggedFrame, RunEvent, RunMetrics, RunRecord
from ..scenarios.config import OBJECT_TRACK_PERIOD_S, Scenario
from ..world.driver_models import Pedals, make_driver
from ..world.ego import Ego, EgoBody
from ..world.gateway import Actuation, Gateway
from ..world.steering_gateway import STEERING_IDS, SteeringGateway
from ..world.plant import divides_step, finite_check, open_plant
from ..world.plant_fmu import DERIVED_WHEEL_SPEEDS, PlantSample
from ..world.radar2d import Track
from ..world.radar_model import RadarModel
from ..world.corner_radar import CornerFeed, forward_feed
from ..world.radar_tracks import radar_params
from ..world.scene import Scene
from ..world.scene_build import build_objects, build_road
from ..world.scene_contact import ContactWatch, Hit
from ..world.scene_objects import SceneObject
from ..world.steering_models import make_steering
from ..results.run_record import pose_cells, timeseries_columns
from .cycle_handoff import Outgoing
from .ecu_config import ecu_config
from .phase_timer import PHASES, PhaseTimer, instrument
from .planar_frames import PlanarFrames, RegionCells, tracks_2d

log = logging.getLogger(__name__)

_WHEEL_MAX_KMH = signal_layout("WheelSpeeds", "WheelSpeedFL").maximum
__all__ = ["PHASES", "ClosedLoop", "ecu_config", "run_scenario"]

Progress = Callable[[float, float], None]
#: bodies a run's scene adds after its scenario's objects, given the index of the first (a fleet's other cars)
Others = Callable[[int], "list[SceneObject]"]


class ClosedLoop:
    """One run of one strategy. Build, then :meth:`run`; the FMU and buses are closed after."""

    def __init__(self, scenario: Scenario, fmu_path: Path, strategy: str | None = None,
                 profile: bool = False, ecu: EcuOptions | None = None, batch_steps: bool = True,
                 others: Others | None = None) -> None:
        self.sc = scenario
        self.strategy = strategy or scenario.ecu.strategy
        self._ecu_cfg = ecu_config(scenario, self.strategy)
        self.h_s = scenario.scenario.step_s
        self.n_sub = int(round(ECU_CYCLE_S / self.h_s))
        self.n_track = int(round(OBJECT_TRACK_PERIOD_S / ECU_CYCLE_S))
        self._world(scenario, others)
        self.driver = make_driver(scenario.driver, scenario.scenario.seed)
        self.radar = RadarModel(scenario.radar, default_rng(scenario.scenario.seed))
        self.ecu = ecu if ecu is not None else EcuOptions()
        key = run_key(self.ecu, self._ecu_cfg)  # SecOC: None means E2E protection only
        self._signer = SecOcSender(key) if key is not None else None
        self.gateway = Gateway(scenario.gateway, conflict_window_cycles=10 if self.ecu.realtime else 1, key=key)
        self.steering_gateway = SteeringGateway(scenario.gateway.override_timeout_s, key,
                                                lockstep=not self.ecu.realtime)
        self._overlay_rad = self._overlay_next_rad = 0.0  # its steer_request: this cycle's, the next one's
        self._planar = PlanarFrames()
        #: the planar sensors' frames (EscDynamics, RadarTrack0..7): sent only to an ECU equipped with them
        self._planar_inputs = EQUIPMENT[self._ecu_cfg.equipment].planar
        self._region = RegionCells()
        self.record = RunRecord(self.strategy, RunMetrics(self.strategy),
                                columns=timeseries_columns(scenario, len(self.scene.objects)))
        # bound once: next() of each message's E2E counter (C-level), called every cycle
        self._next_driver, self._next_wheels, self._next_track = (
            CounterSequence().next for _ in range(3))
        # the link before the plant: a spawned ECU (--ecu process) starts up while the FMU loads. Saves
        # at most the FMU's load (8-12 ms measured here), within the noise of the ECU's ~0.17 s start-up
        self.link = open_link(self.ecu, self._ecu_cfg, ECU_CYCLE_S, key)
        try:
            self.plant = open_plant(scenario.plant, fmu_path)
        except BaseException:
            self.link.close()  # stops a spawned ECU by its PID and leaves the bus
            raise
        self._check_sample = finite_check(scenario.plant)  # NaN/Inf output: an error naming time and variable
        self.record.fmu_path, self.record.fmu_sha256 = str(fmu_path), self.plant.sha256
        if not self.plant.wheel_speeds_mapped:
            self.record.events.append(RunEvent(0.0, "warning", DERIVED_WHEEL_SPEEDS))
            log.warning("%s: %s", self.strategy, DERIVED_WHEEL_SPEEDS)
        self.batch_steps = batch_steps and divides_step(self.plant.fixed_internal_step_s, self.h_s)
        self._timer: PhaseTimer | None = instrument(self) if profile else None

    def _world(self, scenario: Scenario, others: Others | None) -> None:
        """The road, the ego's body, the scene and its contact watch, the steering, the 2-D radar (planar runs).
        ``others``: bodies the scenario does not declare, after its objects (the other vehicles of a fleet)."""
        road = build_road(scenario.road)
        self.ego_body = EgoBody(scenario.plant)
        objects = build_objects(scenario, road)
        objects += others(len(objects)) if others is not None else []
        self.scene = Scene(objects, self.ego_body, scenario.radar, scenario.end)
        self._has_scene = bool(self.scene)  # its objects are fixed: asked once, not 4x per cycle (Scene.__bool__)
        self.watch = ContactWatch(self.scene)
        self.steering = make_steering(scenario.driver.steering, road, scenario.plant)
        #: planar runs: pose columns, the contact in metrics and events, the 2-D tracks every radar cycle
        self.planar = scenario.planar
        params = radar_params(scenario.radar, self.ego_body, scenario.scenario.seed)
        fitted = scenario.radar.front_corner  # the front corner radars: their tracks join the forward radar's
        self.tracks = forward_feed(self.scene, params, self.ego_body, fitted) if self.planar else None
        #: the rear corner radars' merged tracks (``[radar] corner``, planar runs; cosim.world.corner_radar)
        self.corner = CornerFeed(self.scene, params, self.ego_body) if self.planar and scenario.radar.corner else None

    # -- one cycle ------------------------------------------------------------
    def _frames_out(self, cycle: int, sample: PlantSample, pedals: Pedals,
                    tracks: tuple[Track, ...] | None = None, steering_rad: float = 0.0,
                    corner: tuple[Track, ...] | None = None) -> list:
        """This cycle's frames to the ECU. ``tracks``: the 2-D radar's tracks on its report cycles (the same
        cycles as ``ObjectTrack``; None on the others, and in 1-D runs), for the planar contract to encode;
        ``corner``: the rear corner radars' on the same cycles (None: not fitted)."""
        top, k = _WHEEL_MAX_KMH, KMH_PER_MPS
        # the four clamps written out, not a list comprehension (1.08 instead of 1.39 µs, timeit)
        w_fl, w_fr, w_rl, w_rr = sample.wheel_speeds_mps
        out = [  # the driver's steering wheel: 0 for the drivers that hold it straight (every 1-D run)
            encode("DriverInput", {"AccelPedal": pedals.accel_pct, "BrakePedal": pedals.brake_pct,
                                   **self._planar.steering_wheel(steering_rad)}, self._next_driver()),
            encode("WheelSpeeds", {"WheelSpeedFL": min(top, max(0.0, w_fl * k)),
                                   "WheelSpeedFR": min(top, max(0.0, w_fr * k)),
                                   "WheelSpeedRL": min(top, max(0.0, w_rl * k)),
                                   "WheelSpeedRR": min(top, max(0.0, w_rr * k))}, self._next_wheels()),
        ]
        if self._planar_inputs:  # EscDynamics and the RadarTrack slots: to an ECU with the planar sensors
            out.append(self._planar.esc_of(sample.yaw_rate_radps, sample.ay_mps2, sample.ax_mps2))
        if cycle % self.n_track == 0:
            out.append(encode("ObjectTrack", self.radar.measure().signals(), self._next_track()))
            if self._planar_inputs:  # the 2-D radar's tracks
                out += self._planar.tracks(tracks_2d(tracks))
                if corner is not None:  # the rear corner radars' tracks: to an ECU with them fitted
                    out += self._planar.corner_tracks(tracks_2d(corner))
        if self._signer is not None:  # each frame followed by its SecOC authenticator
            sign = self._signer.authenticator
            signed = []
            for msg in out:  # a loop, not a nested comprehension (its call: 0.26 instead of 0.67 µs, timeit)
                signed += (msg, sign(msg))
            out = signed
        return out

    def cycle_out(self, t_s: float, cycle: int) -> Outgoing:
        """First half of a cycle: read the plant, run the models, send this cycle's frames to the ECU."""
        self.link.pace(cycle)
        sample = self.plant.read()
        self._check_sample(sample, t_s)
        scene, has_scene = self.scene, self._has_scene
        ego = self.ego_body.at(sample)
        gap_m = scene.observe(t_s, ego) if has_scene else float("inf")
        pedals = self.driver(t_s, sample.position_m, sample.speed_mps)
        steering_rad = 0.0 if self.steering is None else self.steering(t_s, ego)
        truth = scene.radar_truth(t_s, ego) if has_scene else None
        if truth is not None:
            self.radar.sample(truth.gap_m, truth.range_rate_mps, truth.lateral_m)
        else:
            self.radar.sample(None, 0.0)
        tracks = None if self.tracks is None else self.tracks.step(cycle, t_s, ego)
        corner = None if self.corner is None else self.corner.step(cycle, t_s, ego)
        frames = self._frames_out(cycle, sample, pedals, tracks, steering_rad, corner)
        frames.extend(self.link.send(t_s, cycle, frames))
        return Outgoing(sample, ego, pedals, steering_rad, gap_m, frames)

    def cycle_in(self, t_s: float, cycle: int, out: Outgoing, applied: Actuation) -> Actuation:
        """Second half: take the ECU's frames, compute next cycle's commands, log the cycle."""
        received = self.link.collect(t_s, cycle)
        offer, steer = self.gateway.offer, self.steering_gateway.offer
        for msg in received:
            if msg.arbitration_id in STEERING_IDS:
                steer(msg, t_s)
            else:
                offer(msg, t_s)
        nxt = self.gateway.actuation(out.pedals, t_s, out.steering_rad)
        # the EPS's overlay, checked and ramped every cycle: the plant's steer_request from the next cycle, as nxt
        self._overlay_rad, self._overlay_next_rad = self._overlay_next_rad, self.steering_gateway.steer_request_rad(t_s)
        self._log_cycle(t_s, out, received, applied)
        return nxt

    def _log_cycle(self, t_s: float, out: Outgoing, received: list, applied: Actuation) -> None:
        # appended in two plain loops, not a nested comprehension + extend (1.89 instead of 2.08 µs, 7 frames)
        append = self.record.frames.append
        for msg in out.frames:
            append(LoggedFrame._make((t_s, msg.arbitration_id, bytes(msg.data))))
        for msg in received:
            append(LoggedFrame._make((t_s, msg.arbitration_id, bytes(msg.data))))
        sample, pedals, gap_m = out.sample, out.pedals, out.gap_m
        speed_mps = sample.speed_mps
        row = (t_s, sample.position_m, speed_mps, sample.accel_mps2, applied.throttle, applied.brake,
               self.gateway.mode, gap_m, pedals.accel_pct, pedals.brake_pct)
        if self.planar:
            row += pose_cells(out.ego, applied.steering_wheel_angle_rad, self.scene, t_s)
            row += (*self._region.cells(received), self._overlay_rad)
        self.record.rows.append(row)
        # the metrics' running extremes here, where the row is built (once a cycle, after the ECU's
        # frames), not in a call of their own that read the row back (0.39 instead of 0.44-0.52 µs, timeit)
        m = self.record.metrics
        m.min_gap_m = gap_m if m.min_gap_m is None else min(m.min_gap_m, gap_m)
        m.max_speed_mps = max(m.max_speed_mps, speed_mps)

    def _advance(self, k: int, applied: Actuation, ego: Ego) -> tuple[int, bool]:
        """Advance the plant one ECU cycle from the ego at its start; returns the new ``k`` and whether it collided."""
        plant, h = self.plant, self.h_s
        watching = self.actuate(k, applied, ego)
        if self.batch_steps and not watching:
            plant.step(k * h, self.n_sub * h)
            return k + self.n_sub, False
        for _ in range(self.n_sub):
            plant.step(k * h, h)
            k += 1
            if watching and self.touches(k):
                return k, True
        return k, False

    def actuate(self, k: int, applied: Actuation, ego: Ego) -> bool:
        """The plant's commands for the cycle from step ``k``; whether a body could touch the ego within it."""
        self.plant.set_actuation(applied.throttle, applied.brake, applied.steering_wheel_angle_rad, self._overlay_rad)
        return self._has_scene and self.watch.candidates(k * self.h_s, ego, self.n_sub * self.h_s)

    def touches(self, k: int) -> bool:
        """Whether a watched body touches the ego at step ``k`` (then the contact is recorded)."""
        hit = self.watch.contact(k * self.h_s, self.ego_body.at(self.plant.pose()))
        if hit is not None:
            self.collide(hit)
        return hit is not None

    def collide(self, hit: Hit) -> None:
        m = self.record.metrics
        m.collided = True
        m.impact_speed_mps = hit.impact_speed_mps
        m.min_gap_m = hit.gap_m if m.min_gap_m is None else min(m.min_gap_m, hit.gap_m)
        detail = f"relative impact speed {m.impact_speed_mps:.3f} m/s"
        data = None
        if self.planar:  # 1-D runs keep their files as they were
            self.record.contact = hit.as_dict()
            data = {k: self.record.contact[k] for k in ("x_m", "y_m", "normal", "object")}
        self.record.events.append(RunEvent(hit.t_s, "collision", detail, data))
        log.info("%s: collision at t=%.3f s, %.2f m/s", self.strategy, hit.t_s, m.impact_speed_mps)

    # -- the run -----------------------------------------------------------------
    def run(self, progress: Progress | None = None) -> RunRecord:
        """Run to the scenario's duration, a collision or an FMI error; always closes the FMU and buses."""
        wall0 = time.perf_counter()
        duration_s = self.sc.scenario.duration_s
        total_k = int(round(duration_s / self.h_s))
        k, cycle, applied = 0, 0, Actuation(0.0, 0.0, 0.0)
        try:
            self.link.start()
            with SafePoints() as signals:  # a signal ends the run between two cycles, never within one
                noted = signals.noted
                while k < total_k:
                    t_s = k * self.h_s
                    out = self.cycle_out(t_s, cycle)
                    nxt = self.cycle_in(t_s, cycle, out, applied)
                    if self.ended(t_s, out.ego):
                        break
                    k, collided = self._advance(k, applied, out.ego)
                    applied, cycle = nxt, cycle + 1
                    if progress is not None and cycle % 100 == 0:
                        progress(k * self.h_s, duration_s)
                    if collided:
                        break
                    if noted:
                        signals.act()  # raises here (KeyboardInterrupt, below), with every cycle whole
            if not self.record.metrics.collided:
                self.final_sample(k * self.h_s)
        except FmiStepError as exc:
            self.stop_on(exc.time_s, "fmi_error", str(exc))
        except EcuStallError as exc:
            self.stop_on(exc.time_s, "ecu_stalled", str(exc))
        except KeyboardInterrupt as exc:  # SIGINT, or SIGTERM via cosim.cli.signals: keep what was run
            self.record.interrupted = signal_name(interrupt_signal(exc))
            self.record.events.append(RunEvent(k * self.h_s, "interrupted", f"{self.record.interrupted}: "
                                               f"stopped at t = {k * self.h_s:.3f} s, results so far kept"))
        finally:
            self.close()
        self.finish(k * self.h_s, time.perf_counter() - wall0, cycle)
        return self.record

    def stop_on(self, t_s: float, kind: str, message: str) -> None:
        """An error that ends the run early; the record keeps everything up to ``t_s``."""
        self.record.error = message
        self.record.events.append(RunEvent(t_s, kind, message))
        log.error("%s: %s", self.strategy, message)

    def ended(self, t_s: float, ego: Ego) -> bool:
        """An ``[end]`` condition has been met (recorded as an ``end`` event)."""
        reason = self.scene.end_reason(t_s, ego) if self._has_scene else None
        if reason is not None:
            self.record.metrics.end_reason = reason
            self.record.events.append(RunEvent(t_s, "end", reason))
        return reason is not None

    def final_sample(self, t_s: float) -> None:
        """Final sample at the end of the run (outputs after the last step)."""
        sample = self.plant.read()
        self._check_sample(sample, t_s)
        gap = self.scene.path_gap(t_s, self.ego_body.at(sample))[0] if self.scene else None
        gap = gap if gap is None or math.isfinite(gap) else None
        m = self.record.metrics
        m.final_gap_m = gap
        if gap is not None:
            m.min_gap_m = min(m.min_gap_m, gap) if m.min_gap_m is not None else gap
        m.max_speed_mps = max(m.max_speed_mps, sample.speed_mps)

    def finish(self, t_s: float, wall_s: float, cycles: int) -> None:
        m = self.record.metrics
        m.sim_time_s = t_s
        m.wall_time_s = wall_s
        m.contingency_invocations = self.gateway.contingency_invocations
        m.fault_entries = self.gateway.fault_entries
        self.gateway.finish(t_s)
        if m.min_gap_m is not None and not math.isfinite(m.min_gap_m):
            m.min_gap_m = None
        self.record.events = merge_events(self.link.events, self.gateway.events, self.steering_gateway.events,
                                          self.record.events)
        report = self.link.report()
        self.record.timing = dict(report.timing)
        self.record.ecu_report = report.ecu_report
        self.record.ecu_join_wait_s = report.join_wait_s
        self.record.ecu_settings = report.ecu_settings
        self.record.events.sort(key=lambda e: e.t_s)
        if self._timer is not None and cycles:
            self.record.cycle_cost_s = self._timer.per_cycle_s(cycles)

    def close(self) -> None:
        """Free the FMU, stop an ECU process the run spawned and leave the bus; safe to call twice."""
        try:
            self.plant.close()
        finally:
            self.link.close()


def run_scenario(scenario: Scenario, fmu_path: Path, strategy: str | None = None,
                 progress: Progress | None = None, profile: bool = False,
                 ecu: EcuOptions | None = None) -> RunRecord:
    """Build and run one closed loop; see :class:`ClosedLoop` (``ecu``: where the ECU runs)."""
    return ClosedLoop(scenario, fmu_path, strategy, profile, ecu).run(progress)
