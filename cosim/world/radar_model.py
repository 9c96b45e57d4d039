"""Forward radar: range, range rate and lateral offset of one object, every 50 ms.

Which object, and whether it is inside the field of view, is the scene's
choice (:meth:`cosim.world.scene.Scene.radar_truth`); this model adds the
sensor's imperfections to that truth.

Range is front bumper → object rear (m), range rate its derivative (m/s,
negative closing), matching ``ObjectTrack``. Imperfections, all seeded:

* latency: the reported values are those of ``latency_s`` earlier, rounded
  to whole ECU cycles (the master samples the truth once per cycle);
* noise: zero-mean Gaussian, ``N(0, range_noise_std_m²)`` and
  ``N(0, range_rate_noise_std_mps²)``, from :class:`numpy.random.Generator`;
* maximum range and dropouts (per update, probability
  ``dropout_probability``): reported as ``ObjectValid = 0`` (no target).

Reported values are clipped to the DBC ranges (0..250 m, ±100 m/s). An object whose range or lateral
offset lies beyond what ``ObjectTrack`` can carry (250 m; ±20 m to the side) is not reported: it is
outside the field the contract gives this radar (a crossing cyclist 22 m to the side stopped the run
with a SignalError before).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from can_dbc import ECU_CYCLE_S, signal_layout

from ..scenarios.config import RadarConfig

DBC_RANGE_MAX_M = signal_layout("ObjectTrack", "ObjectRange").maximum
DBC_RATE_MAX_MPS = signal_layout("ObjectTrack", "ObjectRangeRate").maximum
_LATERAL = signal_layout("ObjectTrack", "ObjectLateral")


@dataclass(frozen=True, slots=True)
class Track:
    """One ``ObjectTrack`` update in SI units."""

    valid: bool
    range_m: float
    range_rate_mps: float
    lateral_m: float = 0.0

    def signals(self) -> dict[str, float]:
        """The ``ObjectTrack`` signals in DBC units."""
        if not self.valid:
            return {"ObjectValid": 0, "ObjectRange": 0.0, "ObjectRangeRate": 0.0, "ObjectLateral": 0.0}
        return {"ObjectValid": 1, "ObjectRange": self.range_m,
                "ObjectRangeRate": self.range_rate_mps, "ObjectLateral": self.lateral_m}


NO_TARGET = Track(False, 0.0, 0.0)


class RadarModel:
    """Samples the true gap each ECU cycle; :meth:`measure` returns a delayed, noisy track."""

    def __init__(self, cfg: RadarConfig, rng: np.random.Generator) -> None:
        self._cfg = cfg
        self._rng = rng
        self._delay_cycles = int(round(cfg.latency_s / ECU_CYCLE_S))
        self._history: deque[tuple[float, float, float] | None] = deque(maxlen=self._delay_cycles + 1)

    def sample(self, gap_m: float | None, range_rate_mps: float, lateral_m: float = 0.0) -> None:
        """Record the truth of this ECU cycle (``gap_m=None``: no object in the lane)."""
        self._history.append(None if gap_m is None else (gap_m, range_rate_mps, lateral_m))

    def measure(self) -> Track:
        """The track to send now: the sample ``latency`` old, with noise, range limit and dropout."""
        truth = self._history[0] if len(self._history) > self._delay_cycles else None
        cfg = self._cfg
        # Draw every random number every update, so the stream does not depend on the branch taken.
        # as Python floats (the same values): NumPy scalars made every later operation and the
        # frame's encoding several times slower (measure() + encode: 12 -> 5 µs, measured)
        noise_r, noise_rr = self._rng.standard_normal(2).tolist()
        dropped = self._rng.random() < cfg.dropout_probability
        if truth is None or dropped:
            return NO_TARGET
        gap_m, rate_mps, lateral_m = truth
        range_m = gap_m + cfg.range_noise_std_m * noise_r
        if gap_m > cfg.max_range_m or range_m > DBC_RANGE_MAX_M or not _LATERAL.minimum <= lateral_m <= _LATERAL.maximum:
            return NO_TARGET
        rate = rate_mps + cfg.range_rate_noise_std_mps * noise_rr
        return Track(True, min(max(range_m, 0.0), DBC_RANGE_MAX_M),
                     min(max(rate, -DBC_RATE_MAX_MPS), DBC_RATE_MAX_MPS), lateral_m)
