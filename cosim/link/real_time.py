"""Real time with an ECU on a bus: the master paces itself to the wall clock; the ECU runs on its own.

The master starts cycle ``k`` at the absolute wall-clock deadline
``t0 + k * cycle_s`` and takes whatever the ECU (running ``EcuNode.run``)
sent since the previous cycle. Lag (start - deadline) and jitter
(|period - cycle_s|) of the master's cycle starts are reported, with the same
definitions as :mod:`ecu.scheduler`. No frame at all for ``reply_timeout_s``:
``ecu_lost``.
"""

from __future__ import annotations

import time

import can

from ecu import EcuConfig, Percentiles

from .bus_link import BusLink
from .ecu_link import EcuOptions, LinkReport

#: the last part of a wait for a deadline spent polling rather than sleeping (s): an OS wake-up can be late
_SPIN_S = 0.002


class RealTimeLink(BusLink):
    """An :class:`~cosim.link.ecu_link.EcuLink` paced to the wall clock (process or attach)."""

    realtime = True

    def __init__(self, options: EcuOptions, config: EcuConfig, cycle_s: float, key: bytes | None = None) -> None:
        super().__init__(options, config, key)
        self._cycle_s = cycle_s
        self._lag: list[float] = []
        self._jitter: list[float] = []
        self._t0 = 0.0
        self._prev_start: float | None = None
        self._last_rx_wall = 0.0

    def start(self) -> None:
        """Wait for the ECU's first frame and its announcement, with settings that fit; then start the clock."""
        self._join(first_frame_joins=True)
        self._t0 = time.perf_counter()
        self._last_rx_wall = time.monotonic()

    def pace(self, cycle: int) -> None:
        """Wait for cycle ``cycle``'s wall-clock deadline; record lag and jitter."""
        deadline = self._t0 + cycle * self._cycle_s
        while (remaining := deadline - time.perf_counter()) > 0.0:
            time.sleep(remaining if remaining > _SPIN_S else 0.0)
        start = time.perf_counter()
        self._lag.append(start - deadline)
        if self._prev_start is not None:
            self._jitter.append(abs(start - self._prev_start - self._cycle_s))
        self._prev_start = start

    def send(self, t_s: float, cycle: int, frames: list[can.Message]) -> list[can.Message]:
        for msg in frames:
            self.endpoint.send(msg, t_s)
        return []

    def collect(self, t_s: float, cycle: int) -> list[can.Message]:
        """Whatever has arrived; ``ecu_lost`` after ``reply_timeout_s`` without a frame."""
        endpoint = self.endpoint
        received = endpoint.drain(t_s, [])
        now = time.monotonic()
        if received:
            self._last_rx_wall = now
        elif not endpoint.lost and now - self._last_rx_wall > self.options.reply_timeout_s:
            endpoint.lose(t_s, f"no frame from the ECU for {now - self._last_rx_wall:.3f} s wall time "
                               f"(timeout {self.options.reply_timeout_s} s)")
        return received

    def report(self) -> LinkReport:
        timing = {}
        if self._lag:
            lag = Percentiles.of(self._lag, max(self._lag))
            jit = Percentiles.of(self._jitter, max(self._jitter, default=0.0))
            timing = {"lag_p50_s": lag.p50, "lag_p99_s": lag.p99, "lag_max_s": lag.max,
                      "jitter_p50_s": jit.p50, "jitter_p99_s": jit.p99, "jitter_max_s": jit.max}
        return LinkReport(timing, self.endpoint.ecu_report, self.endpoint.join_wait_s, self._ecu_settings)
