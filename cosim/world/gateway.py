"""The actuator gateway: plays the brake and powertrain ECUs (node ESC).

It checks every ``SafetyOverride`` like any receiver (E2E CRC, counter,
range, via :class:`can_dbc.Receiver`) and applies it to the driver's pedals:

* throttle = min(AccelPedal, ThrottleLimit) while ``OverrideActive``, else AccelPedal;
* brake    = max(BrakePedal, BrakeDecelRequest / brake_full_decel_mps2), clipped to 1.

If no fresh valid ``SafetyOverride`` arrived within ``override_timeout_s``,
or the receiver's E2E validity score says the message is invalid, it falls
back to the driver's commands alone and records an event; it records another
when valid frames return. Time is passed in; nothing reads a clock.

A second ECU on the bus: one ECU sends one ``SafetyOverride`` per 10 ms
cycle. When more than ``conflict_window_cycles + conflict_slack`` of them
arrive within the last ``conflict_window_cycles`` cycles (lock-step: window 1,
slack 0, i.e. two in one cycle; real time: window 10, slack 3) the gateway
records a ``second_ecu`` event, logs a warning and reports mode ``SECOND_ECU``
until ``CONFLICT_HOLD_S`` (1 s) has passed without an excess (the two senders'
frames need not fall evenly into cycles, so a bare per-cycle test would
flicker). In lock-step the interleaving is itself proof: one ECU sends exactly
one frame per cycle with the next counter, so a repeated or jumping counter
also marks a second sender, however the two senders' frames fall into cycles.
In real time a count alone is not proof: a stalled master (the host took the
CPU for tens of ms) takes several cycles' frames at once. So there an excess
counts only together with a repeated or jumping counter in the same window,
which one sender never produces (its counter steps by one; a lost frame or two
stays within the E2E tolerance), while two interleaved senders always do
(their counters cannot both step by 1 to 2 modulo 15). When one sender
remains, the ``override_restored`` event marks the return.

What a conflict applies (issue 25; the safety argument is ``docs/security.md``):
two senders of one CAN message cannot be told apart, so the gateway does not
pick one. While the override's sender is in doubt -- a second sender detected,
or within ``CONFLICT_HOLD_S`` of a sign of one: a repeated or jumping counter,
or a message resynchronising -- it applies the *most restrictive* demand of every structurally valid
``SafetyOverride`` (CRC, DLC, ranges and enumerations hold; authenticated when
keyed; the counter is not asked) received within the last
``override_timeout_s``: the lowest throttle limit (100 % for a frame with
``OverrideActive`` 0) and the highest ``BrakeDecelRequest``. A frame of doubted
origin can therefore only add restriction, never remove it: the car is
limited and braked at least as much as by the working ECU whose frames are
among them, and a forger's pass-through frame changes nothing. The price is
that a forger's braking frame is obeyed too (phantom braking) while the doubt
lasts; the run reports it (``second_ecu``, exit 4). Without any valid frame
for ``override_timeout_s`` the gateway falls back to the driver, as after a
timeout. Before issue 25 a conflict made it ignore every override (driver
only): a forger sending one pass-through frame after every third genuine one
disarmed the ECU, and the car hit the cyclist at 33.8 m/s.

Authentication (issue 15): with a key, a ``SafetyOverride`` is obeyed only
once its SecOC authenticator verifies (:mod:`can_dbc.secoc`); a forged,
replayed or unauthenticated one is rejected and counted, and the first such
frame records an ``auth_failure`` event (a summary with the count follows at
the end of the run: :meth:`Gateway.finish`). The ECU's own findings arrive in
``EcuStatus``: ``FaultAuth`` or ``FaultForeignOverride`` there records an
``ecu_security_fault`` event once. A run with either event exits non-zero.
"""

from __future__ import annotations

import logging
from collections import deque
from typing import NamedTuple

import can

from can_dbc import (AUTHENTICATORS, LAYOUTS, MODE_NAMES, AuthError, CounterError, FrameError, Receiver, SecOcVerifier,
                     check_alone)

from .driver_models import Pedals
from ..results.run_record import RunEvent
from ..scenarios.config import GatewayConfig

log = logging.getLogger(__name__)

TIMEOUT_MODE = "NO_OVERRIDE"  # reported while falling back to the driver alone
CONFLICT_MODE = "SECOND_ECU"  # reported while two ECUs send SafetyOverride
_OVERRIDE_ID = LAYOUTS["SafetyOverride"].frame_id
#: a detected second sender keeps mode SECOND_ECU until this long (s) without an excess.
CONFLICT_HOLD_S = 1.0
_MODE_NAMES = MODE_NAMES  # the DBC's VAL_ of SafetyOverride.Mode
_CONTINGENCY = next(code for code, name in MODE_NAMES.items() if name == "CONTINGENCY")
_STATUS_ID = LAYOUTS["EcuStatus"].frame_id
_IDENTITY_IDS = (LAYOUTS["EcuIdentity"].frame_id, AUTHENTICATORS["EcuIdentity"])
#: frames of the ECU that are not the brake's business: its announcement (the link's, cosim.link.ecu_identity) and
#: its region status (the time series', cosim.loop.planar_frames.RegionCells)
_NOT_OURS = (*_IDENTITY_IDS, LAYOUTS["EcuRegionStatus"].frame_id)
#: event kinds that make a run exit non-zero (cosim.cli)
SECURITY_EVENTS = ("auth_failure", "ecu_security_fault")


class Actuation(NamedTuple):
    """Plant commands: throttle and brake 0..1, and the driver's steering-wheel angle (rad), passed through.

    A tuple: built every cycle, about 4x cheaper than a frozen dataclass.
    """

    throttle: float
    brake: float
    steering_wheel_angle_rad: float = 0.0


class Gateway:
    """Applies ``SafetyOverride`` frames to the driver's pedals."""

    def __init__(self, cfg: GatewayConfig, conflict_window_cycles: int = 1, key: bytes | None = None) -> None:
        self._cfg = cfg
        self._window: deque[int] = deque(maxlen=conflict_window_cycles)
        self._conflict_limit = conflict_window_cycles + (0 if conflict_window_cycles == 1 else 3)
        self._in_cycle = 0
        # lock-step: one ECU sends exactly one SafetyOverride per cycle with the next counter,
        # so a repeated or jumping counter can only come from a second sender
        self._counters_prove_conflict = conflict_window_cycles == 1
        self._counter_anomaly = False
        self._anomalies: deque[bool] = deque(maxlen=conflict_window_cycles)  # per cycle of the window
        self._conflict_until_t_s = -1.0
        self._doubt_until_t_s = -1.0  # until then the override's sender is in doubt (module docstring)
        self.conflict = False
        self._rx = Receiver(names=["SafetyOverride"], secoc=SecOcVerifier(key) if key is not None else None)
        self._keyed = key is not None
        self.auth_failures = 0
        self._ecu_security_reported = False
        self._last_fresh_t_s = 0.0  # the first timeout window starts at t = 0
        self._last_valid_t_s = 0.0  # the last structurally valid override, whatever its counter (timeout)
        self._last_demand_t_s = -1.0  # the same, from the first frame on
        self._signals: dict | None = None
        # this cycle's valid overrides folded into their most restrictive demand (a flood costs no memory and
        # cannot push a braking frame out), then kept per cycle: (t_s, throttle limit %, decel m/s², contingency)
        self._limit_pct, self._decel_mps2, self._contingency_seen, self._demanded = 100.0, 0.0, False, False
        self._demands: deque[tuple[float, float, float, bool]] = deque()
        self._contingency = False  # whether the command applied now is a contingency (counts its entries)
        self.fallback = False
        self.mode = "STANDBY"
        self.contingency_invocations = 0
        #: entries into the ECU's FAULT after it first left it (start-up FAULT lasts until its inputs are valid)
        self.fault_entries = 0
        self._started = False
        self.events: list[RunEvent] = []  # kinds: override_timeout, override_restored, second_ecu

    def offer(self, msg: can.Message, t_s: float) -> bool:
        """Take one frame from the bus; returns True if it was a fresh valid ``SafetyOverride``."""
        override = msg.arbitration_id == _OVERRIDE_ID and not msg.is_extended_id
        if override and not self._keyed:  # keyed: only authenticated frames count (below)
            self._in_cycle += 1
        elif msg.arbitration_id == _STATUS_ID:
            self._ecu_status(msg, t_s)
            return False
        elif msg.arbitration_id in _NOT_OURS:
            return False
        try:
            frame = self._rx.check(msg)
        except AuthError as exc:
            self._auth_failure(t_s, exc)
            return False
        except CounterError:  # a jump: out of sequence, but the frame itself may be a valid demand
            if override:
                self._out_of_sequence(msg, t_s)
            return False
        except FrameError:
            return False
        if frame is None:  # held until its authenticator arrives
            return False
        if self._keyed:  # a forged frame is rejected above and is no evidence of a second ECU
            self._in_cycle += 1
        alone = t_s != self._last_demand_t_s  # the first valid override of this cycle
        self._valid(frame.signals, t_s)
        if not frame.synced or not frame.fresh:  # resynchronising, or a repeated counter: a second sender?
            self._counter_anomaly = True
            self._signals = None  # neither it nor older data is obeyed as *the* ECU's command
            return False
        mode = _MODE_NAMES[int(frame.signals["Mode"])]  # the receiver checked it against the DBC's VAL_
        if alone and t_s >= self._doubt_until_t_s:  # one sender as far as is known (else: actuation counts)
            if mode == "CONTINGENCY" and not self._contingency:
                self.contingency_invocations += 1
            self._contingency = mode == "CONTINGENCY"
        if mode == "FAULT" and self.mode != "FAULT" and self._started:
            self.fault_entries += 1
        self._started = self._started or mode != "FAULT"
        self.mode = mode
        self._signals = frame.signals  # read only: frames of one payload share it (can_dbc.receiver._DECODED)
        self._last_fresh_t_s = t_s
        return True

    def _out_of_sequence(self, msg: can.Message, t_s: float) -> None:
        """A SafetyOverride with a jumping counter: an anomaly; a demand if the frame itself is valid."""
        self._counter_anomaly = True
        self._signals = None
        try:
            signals = check_alone(msg).signals  # (authenticated already, when keyed)
        except FrameError:
            return
        self._valid(signals, t_s)

    def _valid(self, signals, t_s: float) -> None:
        """Fold a valid override's demand into the cycle's: its throttle limit only while ``OverrideActive``."""
        if signals["OverrideActive"] and signals["ThrottleLimit"] < self._limit_pct:
            self._limit_pct = signals["ThrottleLimit"]
        if signals["BrakeDecelRequest"] > self._decel_mps2:
            self._decel_mps2 = signals["BrakeDecelRequest"]
        if signals["Mode"] == _CONTINGENCY:
            self._contingency_seen = True
        self._demanded = True
        self._last_valid_t_s = self._last_demand_t_s = t_s

    def _auth_failure(self, t_s: float, exc: AuthError) -> None:
        self.auth_failures += 1
        if self.auth_failures == 1:
            detail = f"SafetyOverride rejected: {exc}; only authenticated overrides are obeyed"
            self.events.append(RunEvent(t_s, "auth_failure", detail))
            log.warning("t=%.3f s: %s", t_s, detail)

    def _ecu_status(self, msg: can.Message, t_s: float) -> None:
        """The ECU's security findings, read from each ``EcuStatus`` on its own merits (:func:`check_alone`):
        a report, which two senders' interleaved counters must not hide."""
        if self._ecu_security_reported:
            return
        try:
            frame = check_alone(msg)
        except FrameError:
            return
        found = [name for name in ("FaultAuth", "FaultForeignOverride") if frame.signals[name]]
        if found:
            self._ecu_security_reported = True
            detail = f"the ECU reports {' and '.join(found)} (frames failing authentication or a foreign override)"
            self.events.append(RunEvent(t_s, "ecu_security_fault", detail))
            log.warning("t=%.3f s: %s", t_s, detail)

    def finish(self, t_s: float) -> None:
        """End of run: summarise the authentication failures after the first."""
        if self.auth_failures > 1:
            self.events.append(RunEvent(t_s, "auth_failure", f"{self.auth_failures} SafetyOverride frames "
                                                              "failed authentication in this run (all rejected)"))

    def _update_conflict(self, t_s: float) -> None:
        self._window.append(self._in_cycle)
        if self._counter_anomaly:  # the sender is in doubt for a while, proven or not
            self._doubt_until_t_s = t_s + CONFLICT_HOLD_S
        self._in_cycle = 0
        seen = sum(self._window)
        self._anomalies.append(self._counter_anomaly)
        counters = self._counters_prove_conflict and self._counter_anomaly
        self._counter_anomaly = False
        excess = seen > self._conflict_limit and (self._counters_prove_conflict or any(self._anomalies))
        if excess or counters:
            self._conflict_until_t_s = self._doubt_until_t_s = t_s + CONFLICT_HOLD_S
        conflict = t_s < self._conflict_until_t_s
        if conflict and not self.conflict:
            why = "a repeated or jumping E2E counter" if counters and seen <= self._conflict_limit else \
                f"{seen} frames in {len(self._window)} cycle(s), expected at most {self._conflict_limit}"
            detail = (f"SafetyOverride with {why}: a second ECU is on the bus; the most restrictive of the "
                      "valid overrides is applied")
            self.events.append(RunEvent(t_s, "second_ecu", detail))
            log.warning("t=%.3f s: %s", t_s, detail)
        elif self.conflict and not conflict:
            self.events.append(RunEvent(t_s, "override_restored", "one SafetyOverride sender again"))
            log.info("t=%.3f s: one SafetyOverride sender again", t_s)
        self.conflict = conflict
        if conflict:
            self.mode = CONFLICT_MODE

    def _update_demands(self, t_s: float) -> None:
        """The cycle's folded demand into the window; demands older than ``override_timeout_s`` out."""
        demands = self._demands
        if self._demanded:
            demands.append((t_s, self._limit_pct, self._decel_mps2, self._contingency_seen))
            self._limit_pct, self._decel_mps2, self._contingency_seen, self._demanded = 100.0, 0.0, False, False
        oldest_t_s = t_s - self._cfg.override_timeout_s - 1e-9
        while demands and demands[0][0] < oldest_t_s:
            demands.popleft()

    def _update_fallback(self, t_s: float, doubt: bool) -> None:
        """Driver only after ``override_timeout_s`` without a valid override (in doubt: from any sender)."""
        silent_s = t_s - (self._last_valid_t_s if doubt else self._last_fresh_t_s)
        # in doubt the E2E score is not asked: two senders drive it up; only silence is
        invalid = not doubt and not self._rx.is_valid("SafetyOverride")
        lost = silent_s > self._cfg.override_timeout_s + 1e-9 or invalid
        if lost and not self.fallback:
            detail = (f"no valid SafetyOverride for {silent_s:.3f} s (timeout {self._cfg.override_timeout_s} s),"
                      f" E2E score {self._rx.score('SafetyOverride')}")
            self.events.append(RunEvent(t_s, "override_timeout", detail))
            log.warning("t=%.3f s: %s; driver commands only", t_s, detail)
            self.mode = TIMEOUT_MODE
            self._contingency = False
        elif not lost and self.fallback:
            self.events.append(RunEvent(t_s, "override_restored", "valid SafetyOverride again"))
            log.info("t=%.3f s: SafetyOverride restored", t_s)
        self.fallback = lost

    def _most_restrictive(self) -> tuple[float, float, bool] | None:
        """(throttle limit %, brake decel m/s², any contingency) over the window's demands; None if none."""
        demands = self._demands
        if not demands:
            return None
        return min(d[1] for d in demands), max(d[2] for d in demands), any(d[3] for d in demands)

    def actuation(self, pedals: Pedals, t_s: float, steering_wheel_angle_rad: float = 0.0) -> Actuation:
        """The plant's throttle and brake (0..1) for the cycle starting at ``t_s``, and the driver's steering-wheel
        angle (rad), passed through (no ECU steers yet)."""
        self._update_conflict(t_s)
        self._update_demands(t_s)
        doubt = t_s < self._doubt_until_t_s
        self._update_fallback(t_s, doubt)
        throttle_pct, brake = pedals.accel_pct, pedals.brake_pct / 100.0
        if self.fallback:
            limit_pct = decel_mps2 = None
        elif doubt:  # the sender is in doubt: every valid demand of the window, the most restrictive of each
            limit_pct, decel_mps2, contingency = self._most_restrictive() or (None, None, False)
            if contingency and not self._contingency:
                self.contingency_invocations += 1
            self._contingency = contingency
        elif (sig := self._signals) is not None:
            limit_pct = sig["ThrottleLimit"] if sig["OverrideActive"] else None
            decel_mps2 = sig["BrakeDecelRequest"]
        else:
            limit_pct = decel_mps2 = None
        if limit_pct is not None:
            throttle_pct = min(throttle_pct, limit_pct)
        if decel_mps2 is not None:
            brake = max(brake, decel_mps2 / self._cfg.brake_full_decel_mps2)
        return Actuation._make((min(1.0, max(0.0, throttle_pct / 100.0)), min(1.0, max(0.0, brake)),
                                steering_wheel_angle_rad))

    @property
    def stats(self) -> dict[str, int]:
        return dict(self._rx.stats)
