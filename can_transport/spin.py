"""``AdaptiveSpin``: how long a receiver polls before it blocks, learned per wait, zero on a busy machine.

In lock-step each side waits for the other's answer, which on a quiet
machine comes within a fraction of a millisecond. Blocking then costs an OS
wake-up per wait (20 to 100 µs on the development machine's virtual CPUs);
polling costs nothing extra, because the core would idle anyway. On a busy
machine the same polling is harmful: the poller holds a core that the peer
needs to produce the answer. Measured with two CPU-bound neighbour
processes on 2 cores, a 2 ms poll turned a 10 ms lock-step cycle into
several milliseconds of wall time (the paper run fell from 38x to 6x real
time), while blocking kept it within a factor of two of the quiet figure.

So a receiver polls only when both hold:

1. **there is a core for everyone who wants one**: the number of runnable
   tasks in ``/proc/loadavg`` (field 4, an instantaneous count that includes
   the reader) was at most the number of usable CPUs in the last two samples,
   taken at most every ``SAMPLE_PERIOD_S`` (reading it costs ~10 µs). Without
   ``/proc/loadavg`` it never polls;
2. **the answer usually comes soon**: the budget is twice an exponential
   moving average (weight 1/8) of recent waits (each counted whole, polling
   and blocking, up to ``4 * max_spin_s``); when twice the average exceeds
   ``max_spin_s`` (an idle peer, a slow one) the budget is 0, so a peer that
   slows down stops the polling within a few waits, and one that speeds up
   again starts it (a blocked wait is measured too).

The receiver calls :meth:`budget_s` before a wait and :meth:`waited` after it.
"""

from __future__ import annotations

import os

#: how often /proc/loadavg is read, at most (s)
SAMPLE_PERIOD_S = 0.02
_LOADAVG = "/proc/loadavg"


def usable_cpus() -> int:
    """CPUs this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


class AdaptiveSpin:
    """Per-wait polling budget of one receiver (all times in s).

    Parameters
    ----------
    max_spin_s : float
        The longest a receiver polls before blocking; 0 always blocks.
    loadavg_path : str
        Where the runnable-task count is read (``/proc/loadavg``; tests give a file of their own).
    """

    def __init__(self, max_spin_s: float, loadavg_path: str = _LOADAVG) -> None:
        self.max_spin_s = max_spin_s
        self._cpus = usable_cpus()
        self._mean_wait_s = max_spin_s / 4.0
        self._next_sample = 0.0
        self._quiet = (False, False)  # the last two samples: was there a core for every runnable task?
        self._loadavg_fd: int | None = None
        if max_spin_s > 0.0:
            try:
                self._loadavg_fd = os.open(loadavg_path, os.O_RDONLY | os.O_CLOEXEC)
            except OSError:
                self._loadavg_fd = None  # no way to tell a busy machine: never poll

    @property
    def machine_quiet(self) -> bool:
        """True when the last two samples found no more runnable tasks than CPUs."""
        return self._quiet[0] and self._quiet[1]

    def budget_s(self, now: float) -> float:
        """How long to poll before blocking in a wait that starts at ``now`` (monotonic s)."""
        if self._loadavg_fd is None:
            return 0.0
        if now >= self._next_sample:
            self._sample(now)
        if not (self._quiet[0] and self._quiet[1]):
            return 0.0
        budget = 2.0 * self._mean_wait_s
        return budget if budget <= self.max_spin_s else 0.0

    def waited(self, wait_s: float) -> None:
        """Learn from one wait that ended after ``wait_s`` (polling plus blocking)."""
        cap = 4.0 * self.max_spin_s  # one long idle wait must not dominate the average for long
        self._mean_wait_s += (min(wait_s, cap) - self._mean_wait_s) * 0.125

    def _sample(self, now: float) -> None:
        self._next_sample = now + SAMPLE_PERIOD_S
        try:
            text = os.pread(self._loadavg_fd, 128, 0)
            running = int(text.split()[3].split(b"/")[0])
        except (OSError, IndexError, ValueError):
            self._quiet = (False, False)
            return
        self._quiet = (self._quiet[1], running <= self._cpus)

    def close(self) -> None:
        if self._loadavg_fd is not None:
            os.close(self._loadavg_fd)
            self._loadavg_fd = None
