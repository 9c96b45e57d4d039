"""The reciprocal dance as it shows in the speed trace: separate decelerations with recoveries.

The paper (Johnson 2019, Fig. 2 and its text) reads the dance off the speed
profile: "oscillating speeds toward the ends of the plots". This module
counts it from the logged speed alone (``timeseries.csv``'s ``speed_mps``,
one sample per 10 ms cycle), without the ECU's own contingency count.

Method: a zigzag (peak/trough) detector with hysteresis. Walking the trace,

* while *rising* the running peak ``v_pk`` is tracked; once the speed falls
  ``DROP_MPS`` below it, a **deceleration** begins (counted once);
* while *falling* the running trough ``v_tr`` is tracked; once the speed
  climbs ``RISE_MPS`` above it, the speed has **recovered** and the next fall
  counts as a new, separate deceleration.

So ``n`` decelerations are separated by ``n - 1`` recoveries of at least
``RISE_MPS`` (the last deceleration may end in a stop or a collision). Both
thresholds are ours: 0.5 m/s (1.8 km/h) is about 2 % of the approach speed,
a step that is plain in a 0-30 m/s plot. The logged speed is the plant's
noise-free state, so smaller thresholds find smaller oscillations (the
experiments in ``benchmarks/dance_candidates.py`` also report the largest
recovery with a 0.05 m/s detector). The *amplitude* of the dance is the
mean recovery ``mean(v_pk - v_tr)`` over the recoveries, in m/s.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable

DROP_MPS = 0.5
RISE_MPS = 0.5


@dataclass(frozen=True)
class SpeedDance:
    """Separate decelerations in a speed trace (m/s throughout)."""

    decelerations: int
    #: speed lost in each deceleration (peak to the trough that ends it).
    drops_mps: tuple[float, ...]
    #: speed regained after each deceleration but the last (trough to next peak).
    rises_mps: tuple[float, ...]

    @property
    def amplitude_mps(self) -> float:
        """Mean recovery between decelerations (0 when there is none)."""
        return sum(self.rises_mps) / len(self.rises_mps) if self.rises_mps else 0.0


def speed_dance(speeds_mps: Iterable[float], drop_mps: float = DROP_MPS, rise_mps: float = RISE_MPS) -> SpeedDance:
    """Count separate decelerations (falls >= ``drop_mps`` split by recoveries >= ``rise_mps``)."""
    if drop_mps <= 0.0 or rise_mps <= 0.0:
        raise ValueError(f"thresholds must be positive, got drop {drop_mps}, rise {rise_mps}")
    falling = False
    peak = trough = last_trough = None
    drops: list[float] = []
    rises: list[float] = []
    for v in map(float, speeds_mps):
        if peak is None:
            peak = trough = v
        if not falling:
            peak = max(peak, v)
            if peak - v >= drop_mps:
                if last_trough is not None:
                    rises.append(peak - last_trough)
                falling, trough = True, v
        elif v < trough:
            trough = v
        elif v - trough >= rise_mps:
            drops.append(peak - trough)
            falling, peak, last_trough = False, v, trough
    if falling:
        drops.append(peak - trough)
    return SpeedDance(len(drops), tuple(drops), tuple(rises))
