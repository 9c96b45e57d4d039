"""``EcuNode``: the thin shell that runs the pure core on any ``can.BusABC``.

One cycle (:meth:`EcuNode.step`): drain every frame received since the last
cycle through the E2E receiver (bad frames are counted and ignored; a fresh
frame's receive time is the cycle time ``t_s``, so the same frames at the same
cycle times give the same outputs), run the core, send ``SafetyOverride`` (and
``SteeringOverride`` with steering authority) and, every
``status_period_cycles``-th cycle, ``EcuStatus`` (and ``EcuRegionStatus`` with the planar sensors).
Which frames it receives and sends is its equipment's (``config.equipment``, :mod:`ecu.equipment`): a
frame of a message it is not equipped for is counted as ``UnknownFrame`` and ignored.

Scheduling is separate (:mod:`ecu.scheduler`): lock-step by calling
``step(t_s)``, real time on the wall clock, or sim time paced by ``SimClock``
frames (``config.sim_time``), all through :meth:`EcuNode.run`.

Fail safe inside the cycle: an exception in the core is logged and answered
with a FAULT frame (``ThrottleLimit 0``, internal fault flag; a contingency
in progress keeps braking); a send error is counted and logged.

Standalone (``crd ecu``, issue 25): the node announces itself on the bus
(``EcuIdentity``: its software version, strategy and settings digest,
:mod:`ecu.config_digest`; with a key, authenticated): while it waits for a
run, as its scheduler asks (:meth:`announce`), then in its first cycle and
every 100 cycles. Paced by ``SimClock``, its run starts at ``SimTimeMs`` 0: a
node that has taken no clock yet rejects any other (so a master that resumes a
run after the ECU ended it stalls loudly instead of going on with a fresh ECU).
An ECU the co-simulation steps in its own process is not standalone and sends
no ``EcuIdentity``.

Issue 15: frames are rate-monitored at their cycle time; with a key
(``key`` or ``config.key_file``) every input and ``SimClock`` must carry a
valid SecOC authenticator and ``SafetyOverride`` is sent with one
(:mod:`can_dbc.secoc`). The node's own findings become fault flags held for
``FLAG_HOLD_S``: ``AUTH`` (a frame failed authentication), ``FOREIGN_OVERRIDE``
(a ``SafetyOverride`` on the bus that this ECU did not send: panda's relay-
malfunction rule) and ``CLOCK`` (a ``SimClock`` that does not advance by
1..``MAX_CLOCK_STEP_CYCLES`` cycles is rejected: no cycle runs on it).
"""

from __future__ import annotations

import logging
import math
import threading
from collections import Counter

import can

from can_dbc import (AUTHENTICATORS, ECU_CYCLE_S, LAYOUTS, CounterSequence, Frame, Receiver, SecOcSender,
                     SecOcVerifier, cycle_time_s, encode, load_key_file)

from .bus_port import SIM_CLOCK, InputLatch, override_message, region_message, status_message, steering_message
from .config import STATUS_PERIOD_CYCLES, EcuConfig
from .equipment import EQUIPMENT
from .config_digest import identity_signals
from .core import CoreOutputs, CoreState, FaultFlag, Mode, step as core_step
from .scheduler import RunBoundary, RunReport, run_real_time, run_sim_time

log = logging.getLogger(__name__)
SIM_CLOCK_ID = LAYOUTS[SIM_CLOCK].frame_id
#: the ECU's own requests: one on the bus that this ECU did not send is foreign
_FOREIGN_IDS = frozenset(fid for name in ("SafetyOverride", "SteeringOverride")
                         for fid in (LAYOUTS[name].frame_id, AUTHENTICATORS[name]))
#: how long (s of cycle time) a node finding keeps its fault flag set
FLAG_HOLD_S = 1.0
#: a SimClock may advance by 1 .. this many ECU cycles (E2E tolerates two lost frames likewise)
MAX_CLOCK_STEP_CYCLES = 3
#: a standalone node announces itself every this many cycles in a run (the DBC's EcuIdentity cycle)
IDENTITY_PERIOD_CYCLES = round(cycle_time_s("EcuIdentity") / ECU_CYCLE_S)
if IDENTITY_PERIOD_CYCLES % STATUS_PERIOD_CYCLES:  # _cycle announces within the cycles that send EcuStatus
    raise ValueError(f"the DBC's EcuIdentity cycle: expected a multiple of EcuStatus's {STATUS_PERIOD_CYCLES} "
                     f"cycles, got {IDENTITY_PERIOD_CYCLES}")


class EcuNode:
    """The active-safety ECU on ``bus``. It does not own the bus (the caller shuts it down)."""

    def __init__(self, bus: can.BusABC, config: EcuConfig | None = None, key: bytes | None = None,
                 standalone: bool = False) -> None:
        self.bus = bus
        self.config = config if config is not None else EcuConfig()
        self._identity = identity_signals(self.config) if standalone else None
        self._next_identity = CounterSequence().next
        if key is None and self.config.key_file:
            key = load_key_file(self.config.key_file)
        self._signer = SecOcSender(key) if key is not None else None
        equipment = EQUIPMENT[self.config.equipment]
        self._steers = equipment.steering  # sends SteeringOverride: the ECU has steering authority
        self._planar = equipment.planar  # sends EcuRegionStatus: the stopping region's status (planar sensors)
        self._receiver = Receiver(names=(*equipment.inputs, SIM_CLOCK),
                                  secoc=SecOcVerifier(key) if key is not None else None)
        self._clock_ids = {SIM_CLOCK_ID} | ({AUTHENTICATORS[SIM_CLOCK]} if key is not None else set())
        self._last_clock_s: float | None = None
        self._flag_t_s: dict[int, float] = {}
        self._auth_failures = 0
        self._latch = InputLatch()
        self._state = CoreState()
        self._next_override = CounterSequence().next
        self._next_steering = CounterSequence().next
        self._next_status = CounterSequence().next
        self._next_region = CounterSequence().next
        self._cycle_index = 0
        self._pending: dict[str, Frame] = {}  # sim time: the latest checked frame of each message
        self.outputs: CoreOutputs | None = None
        self._errors: Counter[str] = Counter()

    @property
    def mode(self) -> str:
        """``"STANDBY" | "TIGHTENING" | "CONTINGENCY" | "FAULT"``."""
        return self._state.mode.name

    @property
    def state(self) -> CoreState:
        return self._state

    @property
    def cycles(self) -> int:
        return self._cycle_index

    @property
    def stats(self) -> dict[str, int]:
        """Counts: received frames by outcome (``good``, ``UnknownFrame``, ``ChecksumError``...),
        ``gate_interventions``, ``tx_errors``, ``internal_errors``, ``cycles``."""
        counts = dict(self._receiver.stats)
        counts.update(self._errors)
        counts["gate_interventions"] = self._state.gate_interventions
        counts["cycles"] = self._cycle_index
        return counts

    def step(self, t_s: float) -> CoreOutputs:
        """One cycle at simulation time ``t_s``: drain the bus, run the core, send."""
        # _ingest written out, with the calls bound once: about five frames arrive per cycle
        recv, receive, latch = self.bus.recv, self._receiver.receive, self._latch.ingest
        while (msg := recv(0.0)) is not None:
            frame = receive(msg, t_s)
            if frame is not None:
                latch(frame, t_s)
            elif msg.arbitration_id in _FOREIGN_IDS:
                self._foreign(t_s)
        return self._cycle(t_s)

    @property
    def authenticated(self) -> bool:
        """Whether this node requires and sends SecOC authenticators."""
        return self._signer is not None

    def on_sim_message(self, msg: can.Message) -> CoreOutputs | None:
        """Sim-time pacing: check ``msg`` now; a valid ``SimClock`` frame runs one cycle at SimTimeMs.

        A checked input frame waits for the next ``SimClock``, which gives its receive
        time; only the latest frame of each message waits (the latch keeps only the
        latest anyway), so a flood between two clocks costs no memory (finding 5 of
        issue 15). The rate checks stamp it with the cycle it belongs to: the last
        accepted clock + one cycle.
        """
        if msg.arbitration_id not in self._clock_ids or msg.is_extended_id:
            t_next = None if self._last_clock_s is None else self._last_clock_s + self.config.cycle_s
            frame = self._receiver.receive(msg, t_next)
            if frame is not None:
                self._pending[frame.name] = frame
            elif msg.arbitration_id in _FOREIGN_IDS:
                self._foreign(0.0 if t_next is None else t_next)
            return None
        frame = self._receiver.receive(msg)
        if frame is None or frame.name != SIM_CLOCK:
            return None
        t_s = frame.signals["SimTimeMs"] / 1000.0
        if not self._clock_advances(t_s):
            return None
        pending, self._pending = self._pending, {}
        for earlier in pending.values():
            self._latch.ingest(earlier, t_s)
        return self._cycle(t_s)

    def run(self, stop_event: threading.Event, boundary: RunBoundary | None = None) -> RunReport:
        """Run until ``stop_event`` is set (or ``boundary`` ends the run): on the wall clock, or per SimClock
        if ``config.sim_time``."""
        if self.config.sim_time:
            return run_sim_time(self, stop_event, boundary)
        return run_real_time(self, stop_event, self.config.cycle_s, boundary)

    def announce(self) -> None:
        """Send ``EcuIdentity`` (and its authenticator), if standalone; ``RunActive`` once a frame came in."""
        if self._identity is None:
            return
        in_run = any(self._receiver.stats.values()) or bool(self._errors.get("foreign_overrides"))
        msg = encode("EcuIdentity", {**self._identity, "RunActive": int(in_run)}, self._next_identity())
        self._send(msg)
        if self._signer is not None:
            self._send(self._signer.authenticator(msg))

    def ingest(self, msg: can.Message, t_s: float) -> None:
        """Check one received frame now and latch it as received at cycle time ``t_s``."""
        self._ingest(msg, t_s)

    def _clock_advances(self, t_s: float) -> bool:
        """A SimClock must advance by 1..MAX_CLOCK_STEP_CYCLES cycles; else it is rejected and flagged."""
        last = self._last_clock_s
        cycle = self.config.cycle_s
        if last is None and self._identity is not None and t_s != 0.0:  # standalone: a run starts at 0
            self._errors["clock_errors"] += 1
            log.warning("SimClock %.3f s rejected: a run starts at SimTimeMs 0", t_s)
            return False
        if last is not None and not (0.5 * cycle < t_s - last < (MAX_CLOCK_STEP_CYCLES + 0.5) * cycle):
            self._errors["clock_errors"] += 1
            self._flag_t_s[FaultFlag.CLOCK] = last
            log.warning("SimClock %.3f s after %.3f s rejected (expected +1..%d cycles)",
                        t_s, last, MAX_CLOCK_STEP_CYCLES)
            return False
        self._last_clock_s = t_s
        return True

    def _ingest(self, msg: can.Message, t_s: float) -> None:
        frame = self._receiver.receive(msg, t_s)
        if frame is not None:
            self._latch.ingest(frame, t_s)
        elif msg.arbitration_id in _FOREIGN_IDS:
            self._foreign(t_s)

    def _foreign(self, t_s: float) -> None:
        """A SafetyOverride or SteeringOverride (or an authenticator) this ECU did not send: a relay malfunction."""
        self._flag_t_s[FaultFlag.FOREIGN_OVERRIDE] = t_s
        self._errors["foreign_overrides"] += 1

    def _node_flags(self, t_s: float) -> int:
        """CLOCK, AUTH and FOREIGN_OVERRIDE while within FLAG_HOLD_S of their last finding."""
        stats = self._receiver.stats
        # get(): a Counter's [] on a key never counted calls its Python __missing__ (twice per cycle)
        failures = stats.get("AuthError", 0) + stats.get("FreshnessError", 0)
        if failures != self._auth_failures:
            self._auth_failures = failures
            self._flag_t_s[FaultFlag.AUTH] = t_s
        flags = 0
        for bit, seen_t_s in self._flag_t_s.items():
            if t_s - seen_t_s < FLAG_HOLD_S:
                flags |= 1 << bit
        return flags

    def _cycle(self, t_s: float) -> CoreOutputs:
        inputs = self._latch.inputs(t_s, self._receiver, self._node_flags(t_s))
        try:
            self._state, outputs = core_step(self._state, inputs, self.config)
        except Exception:  # noqa: BLE001 - fail safe inside the cycle
            log.exception("core step failed at t=%.3f s; sending FAULT", t_s)
            self._errors["internal_errors"] += 1
            outputs = self._internal_fault()
        self.outputs = outputs
        self._request(override_message(outputs, self._next_override()))
        if self._steers:
            self._request(steering_message(outputs, self._next_steering()))
        if self._cycle_index % self.config.status_period_cycles == 0:
            if self._planar:  # the region's status first: a lock-step master that waits for EcuStatus has both
                self._send(region_message(outputs, self._next_region()))
            self._send(status_message(outputs, self.config.strategy_code, self._next_status()))
            if self._identity is not None and self._cycle_index % IDENTITY_PERIOD_CYCLES == 0:
                self.announce()
        self._cycle_index += 1
        return outputs

    def _request(self, request: can.Message) -> None:
        """Send one of the ECU's requests, followed by its SecOC authenticator when keyed."""
        self._send(request)
        if self._signer is not None:
            self._send(self._signer.authenticator(request))

    def _internal_fault(self) -> CoreOutputs:
        state = self._state
        braking = state.held_contingency or state.mode == Mode.CONTINGENCY
        decel = self.config.contingency_decel_mps2 if braking else 0.0
        self._state = state._replace(mode=Mode.FAULT, valid_cycles=0, held_contingency=braking,
                                     prev_decel_request_mps2=decel, steer_curvature_1pm=None,
                                     steer_request_rad=0.0)
        return CoreOutputs(
            mode=Mode.FAULT, override_active=True, throttle_limit_pct=0.0,
            brake_decel_request_mps2=decel, fault_flags=1 << FaultFlag.INTERNAL,
            proximity=0.0, stopping_distance_m=0.0, speed_estimate_mps=state.speed_mps,
            disjoint=False, gate_intervened=False,
        )

    def _send(self, msg: can.Message) -> None:
        try:
            self.bus.send(msg)
        except can.CanError as exc:
            self._errors["tx_errors"] += 1
            log.warning("send of 0x%03X failed: %s", msg.arbitration_id, exc)
