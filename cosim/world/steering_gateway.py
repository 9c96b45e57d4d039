"""The steering gateway: plays the EPS (node EPS) for the ECU's ``SteeringOverride``.

It checks every ``SteeringOverride`` as :mod:`cosim.world.gateway` checks
``SafetyOverride`` and turns the accepted requests into the plant's
``steer_request`` input (a road-wheel angle overlay, rad; vr 6 of the builtin plant):

* ranges, E2E and enumerations: :class:`can_dbc.Receiver` (a request beyond the DBC's
  +-40 deg is a ``RangeError``, rejected and counted);
* authenticity: with a key, only frames whose SecOC authenticator verifies count
  (a forged or replayed one is rejected, counted, and the first records an ``auth_failure``
  event, which makes the run exit non-zero as for ``SafetyOverride``);
* rate of change: an active request that moved from the last accepted one faster than
  the DBC's ``SigMaxRate`` (23 deg/s) is refused (``RateOfChange``, counted); the last
  accepted request stays the target. Inactive counts as a request of 0;
* conflict: a repeated or jumping counter, or (lock-step) two valid frames in one cycle,
  puts the sender in doubt for ``CONFLICT_HOLD_S`` (a ``steering_conflict`` event; a second ECU is
  reported once, as ``second_ecu``, by :mod:`cosim.world.gateway`); meanwhile the most restrictive of the
  valid requests of the last ``timeout_s`` applies: none if any is inactive or two disagree
  in sign, else the smallest angle;
* timeout: without a valid frame for ``timeout_s`` the target is 0.

Ramp: the applied overlay moves toward the target at most at ``SigMaxRate`` per second,
also back to 0 (an EPS fades an overlay out; it never drops it in one step).
Time is passed in; nothing reads a clock.
"""

from __future__ import annotations

from collections import Counter, deque

import can

from can_dbc import AUTHENTICATORS, ECU_CYCLE_S, LAYOUTS, AuthError, CounterError, FrameError, Receiver, \
    SecOcVerifier, check_alone
from can_dbc.contract import signal_max_rate, signal_resolution
from can_dbc.units import dbc_per_si

from ..results.run_record import RunEvent
from .gateway import CONFLICT_HOLD_S

#: the frames this gateway takes (the request and its authenticator)
STEERING_IDS = frozenset((LAYOUTS["SteeringOverride"].frame_id, AUTHENTICATORS["SteeringOverride"]))
_DEG_PER_RAD = dbc_per_si("deg")
#: the fastest change of the request (deg/s), from the DBC
MAX_RATE_DEGPS = signal_max_rate("SteeringOverride", "SteerAngleRequest")
_RESOLUTION_DEG = signal_resolution("SteeringOverride", "SteerAngleRequest")


class SteeringGateway:
    """Applies ``SteeringOverride`` frames as a road-wheel angle overlay (rad)."""

    def __init__(self, timeout_s: float, key: bytes | None = None, lockstep: bool = True) -> None:
        self._timeout_s, self._lockstep = timeout_s, lockstep
        self._rx = Receiver(names=["SteeringOverride"], secoc=SecOcVerifier(key) if key is not None else None)
        self._target_deg = 0.0  # the last accepted request (0 while inactive)
        self._accepted_t_s = 0.0
        self._applied_deg = 0.0
        self._in_cycle = 0
        self._doubt_until_t_s = -1.0
        self._demands: deque[tuple[float, float]] = deque()  # (t_s, request deg; 0 = inactive)
        self.counts: Counter[str] = Counter()
        self.events: list[RunEvent] = []

    def offer(self, msg: can.Message, t_s: float) -> bool:
        """Take one frame; True if it was a valid ``SteeringOverride`` accepted as the target."""
        try:
            frame = self._rx.check(msg)
        except AuthError as exc:
            return self._refuse(t_s, "auth_failure", f"SteeringOverride rejected: {exc}")
        except CounterError:  # out of sequence: a second sender? the frame may still be a valid demand
            self._doubt(t_s)
            self._demand(msg, t_s)
            return False
        except FrameError:
            return False
        if frame is None:  # held for its authenticator
            return False
        self._in_cycle += 1
        request_deg = frame.signals["SteerAngleRequest"] if frame.signals["SteerActive"] else 0.0
        self._demands.append((t_s, request_deg))
        if not frame.synced or not frame.fresh:
            self._doubt(t_s)
            return False
        elapsed_s = max(t_s - self._accepted_t_s, ECU_CYCLE_S)
        if abs(request_deg - self._target_deg) > MAX_RATE_DEGPS * elapsed_s + _RESOLUTION_DEG:
            return self._refuse(t_s, "steering_rate", f"SteeringOverride request {request_deg:.2f} deg after "
                                f"{self._target_deg:.2f} deg {elapsed_s:.3f} s earlier: faster than "
                                f"{MAX_RATE_DEGPS:g} deg/s (refused)")
        self._target_deg, self._accepted_t_s = request_deg, t_s
        return True

    def _demand(self, msg: can.Message, t_s: float) -> None:
        try:
            signals = check_alone(msg).signals
        except FrameError:
            return
        self._demands.append((t_s, signals["SteerAngleRequest"] if signals["SteerActive"] else 0.0))

    def _doubt(self, t_s: float) -> None:
        if t_s >= self._doubt_until_t_s:
            self.events.append(RunEvent(t_s, "steering_conflict", "SteeringOverride from a second sender: the "
                                                                  "most restrictive valid steering request applies"))
        self._doubt_until_t_s = t_s + CONFLICT_HOLD_S

    def _refuse(self, t_s: float, kind: str, detail: str) -> bool:
        self.counts[kind] += 1
        if self.counts[kind] == 1:
            self.events.append(RunEvent(t_s, kind, detail))
        return False

    def _restrictive_deg(self) -> float:
        """The most restrictive request of the window: 0 if any is 0 or two differ in sign, else the smallest."""
        requests = [r for _, r in self._demands]
        if not requests or min(requests) <= 0.0 <= max(requests):
            return 0.0
        return min(requests, key=abs)

    def steer_request_rad(self, t_s: float) -> float:
        """The plant's ``steer_request`` (rad) for the cycle starting at ``t_s``, after this cycle's frames."""
        if self._lockstep and self._in_cycle > 1:
            self._doubt(t_s)
        self._in_cycle = 0
        oldest_t_s = t_s - self._timeout_s - 1e-9
        while self._demands and self._demands[0][0] < oldest_t_s:
            self._demands.popleft()
        if t_s < self._doubt_until_t_s:
            target = self._restrictive_deg()
        elif t_s - self._accepted_t_s > self._timeout_s + 1e-9:
            target = 0.0
        else:
            target = self._target_deg
        step = MAX_RATE_DEGPS * ECU_CYCLE_S
        self._applied_deg += min(step, max(-step, target - self._applied_deg))
        return self._applied_deg / _DEG_PER_RAD

    @property
    def stats(self) -> dict[str, int]:
        """The receiver's counts (``good``, ``AuthError``, ``RangeError``...) and the refusals."""
        return {**self._rx.stats, **self.counts}
