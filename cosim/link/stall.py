"""Lock-step with a stalled ECU: wait, with simulated time held, up to a limit; then stop loudly.

In lock-step the master cannot advance simulated time without the ECU's
answer for the cycle: continuing without it (driver only) would silently
change the result. A host hiccup, a debugger, or ``SIGSTOP`` on the ECU
process (finding 8 of issue 15: a 2 s stop once gave ``ecu_lost``, a false
``second_ecu``, a collision and exit 0) must therefore only cost wall time:

* the master waits for the cycle's ``SafetyOverride`` up to ``stall_timeout_s``
  of wall time (``crd run/paper --stall-timeout``, default
  :data:`DEFAULT_STALL_TIMEOUT_S`); simulated time does not advance meanwhile,
  so a stall that ends within the limit leaves the run identical to an
  unstalled one;
* a wait longer than ``note_after_s`` (``--reply-timeout``) is recorded as an
  ``ecu_stall`` event with its length (information, not a fault);
* past the limit the run stops with :class:`~cosim.errors.EcuStallError`
  naming the simulated time, the wait and the ECU process: status ``error``,
  exit 1, results up to that cycle kept.

An ECU that is gone (its process exited, or no peer is left on the bus) is a
different case: ``ecu_lost`` at once, and the gateway falls back to the
driver; that run exits 4 (a fault event) unless ``[checks] expect_events``
lists ``ecu_lost``.
"""

from __future__ import annotations

import logging

from ..errors import EcuStallError
from ..results.events import EventLog
from ..results.run_record import RunEvent

log = logging.getLogger(__name__)

DEFAULT_STALL_TIMEOUT_S = 5.0


class StallWatch:
    """How long a lock-step cycle may wait for the ECU, and what a long wait leaves behind."""

    def __init__(self, note_after_s: float, limit_s: float) -> None:
        self.note_after_s = note_after_s
        self.limit_s = limit_s

    def waited(self, t_s: float, waited_s: float, events: EventLog) -> None:
        """After a reply came: record an ``ecu_stall`` event if the wait was long."""
        if waited_s > self.note_after_s:
            detail = (f"the ECU answered t = {t_s:.3f} s after {waited_s:.3f} s of wall time (limit "
                      f"{self.limit_s:g} s); simulated time was held, the run is unchanged")
            if events.add(RunEvent(t_s, "ecu_stall", detail)):
                log.warning("t=%.3f s: %s", t_s, detail)

    def expired(self, t_s: float, waited_s: float, who: str) -> EcuStallError:
        """The error that stops the run: no answer within the limit."""
        return EcuStallError(f"ECU stalled: no SafetyOverride for t = {t_s:.3f} s within {waited_s:.3f} s of "
                             f"wall time ({who}; --stall-timeout {self.limit_s:g} s); lock-step never continues "
                             "without the ECU, so the run stops here", time_s=t_s)
