"""Frequency monitoring of a cyclic message, in the manner of panda's RX checks.

A message declared with ``GenMsgCycleTime`` ``T`` should arrive ``WINDOW_CYCLES``
(10) times per window ``W = 10·T``. With ``n`` the arrivals in the last ``W``:

* too fast: ``n > FAST_FACTOR · 10`` (more than 25), e.g. a flood: a burst of up
  to 15 cycles' frames (a sender stalled by its host for 150 ms, catching up) passes.
  Measured: a real-time run on this shared 2-core host had master stalls of up to
  104 ms, and a limit of 15 flagged them. A second sender at the same rate (2x)
  is not caught here but by its interleaved counters (the receiver's sequence check);
* too slow: ``n < SLOW_FACTOR · 10`` (fewer than 5) while the message keeps
  arriving, once it has been monitored for a whole window: a sender that lost
  more than half its frames yet never long enough for a timeout. A gap of more
  than ``ACTIVE_CYCLES`` = 5 cycle times (the ECU's timeouts: 50 ms for 10 ms
  messages, 250 ms for ObjectTrack) is a silence, the consumer's timeout and
  not a rate fault; the frame after it restarts the monitoring, so the
  timeout's own recovery rule applies alone (a sender stalled by its host for
  70 ms in a real-time test otherwise stretched the fault by 3 cycles).

A violation makes the message invalid until a whole window has passed
without one. Times are the receiver's cycle times (s), passed in; nothing
reads a clock. Each arrival costs one deque append and one comparison: the
deque holds only the last ``max_count + 1`` arrival times.
"""

from __future__ import annotations

import math
from collections import deque

WINDOW_CYCLES = 10
FAST_FACTOR = 2.5
SLOW_FACTOR = 0.5
ACTIVE_CYCLES = 5
#: tolerance on time comparisons (t = k * 0.01 rounding)
_EPS_S = 1e-6


class RateMonitor:
    """Arrival-rate check of one message with cycle time ``cycle_s``."""

    __slots__ = ("window_s", "active_s", "max_count", "min_count", "_times", "_violation_t_s", "_first_t_s")

    def __init__(self, cycle_s: float) -> None:
        self.window_s = WINDOW_CYCLES * cycle_s
        self.active_s = ACTIVE_CYCLES * cycle_s
        self.max_count = int(math.floor(FAST_FACTOR * WINDOW_CYCLES))
        self.min_count = int(math.ceil(SLOW_FACTOR * WINDOW_CYCLES))
        self._times: deque[float] = deque(maxlen=self.max_count + 1)
        self._violation_t_s = -math.inf
        self._first_t_s: float | None = None

    def arrive(self, t_s: float) -> bool:
        """Record an arrival at ``t_s``; True when it makes the window too fast."""
        times = self._times
        if self._first_t_s is None or t_s - times[-1] > self.active_s + _EPS_S:
            times.clear()
            self._first_t_s = t_s
        times.append(t_s)
        if len(times) > self.max_count and t_s - times[0] < self.window_s - _EPS_S:
            self._violation_t_s = t_s
            return True
        return False

    def too_fast(self, t_s: float) -> bool:
        """A too-fast window ended less than one window before ``t_s``."""
        return t_s - self._violation_t_s < self.window_s - _EPS_S

    def too_slow(self, t_s: float) -> bool:
        """Fewer than ``min_count`` arrivals in the window ending at ``t_s``, while still arriving."""
        first = self._first_t_s
        if first is None or t_s - first < self.window_s - _EPS_S:
            return False
        times = self._times
        if t_s - times[-1] > self.active_s + _EPS_S:
            return False  # silent: a timeout, not a rate fault
        return len(times) < self.min_count or times[-self.min_count] <= t_s - self.window_s + _EPS_S

    def fault(self, t_s: float) -> bool:
        """``too_fast(t_s) or too_slow(t_s)``, written out: the receiver asks it for every input every
        cycle, and the two method calls cost more than their tests (about 0.3 µs per message)."""
        window = self.window_s
        if t_s - self._violation_t_s < window - _EPS_S:
            return True  # too fast
        first, times = self._first_t_s, self._times
        if first is None or t_s - first < window - _EPS_S or t_s - times[-1] > self.active_s + _EPS_S:
            return False  # not monitored for a whole window yet, or silent (a timeout, not a rate fault)
        return len(times) < self.min_count or times[-self.min_count] <= t_s - window + _EPS_S
