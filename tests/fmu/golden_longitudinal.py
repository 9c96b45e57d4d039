"""The longitudinal plant's outputs over several input sequences, as recorded before the plant
became planar: the golden data of the zero-steering test (``test_longitudinal_golden.py``).

``tests/fmu/data/longitudinal_golden.json`` was written by this module (``python -m
tests.fmu.golden_longitudinal FMU``, FMU the FMI 2 build of commit d2cf42d, the last
longitudinal-only plant) and must not be rewritten from a later plant: it is the reference
the planar plant has to reproduce bit for bit with its wheel straight. Per sequence it holds
every output at every ``STRIDE_S``-th communication point as exact hexadecimal floats (to show
where a difference starts) and the SHA-256 of all outputs at every communication point (to
catch any difference at all).

The sequences cover full throttle, ABS braking on a dry road, low friction with a wet patch and
snow, locked wheels without ABS on a slope with a rear-driven variant, the faster brake release
of issue 14, and seeded random inputs on a seeded random mix of communication steps (whole
milliseconds and steps that split the 1 ms grid).
"""

from __future__ import annotations

import hashlib
import json
import random
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from tests.fmu.plant_runner import OUTPUTS, run_plant_at

GOLDEN_PATH = Path(__file__).resolve().parent / "data" / "longitudinal_golden.json"
#: communication points between two stored rows of values, about
STRIDE_S = 0.2
V100_MPS = 100 / 3.6


@dataclass(frozen=True)
class Sequence:
    """One recorded run: communication points in integer microseconds, inputs, parameters."""

    points_us: tuple[int, ...]
    schedule: Callable[[float], dict[str, float]]
    params: dict[str, float] = field(default_factory=dict)


def _even(stop_s: float, step_us: int) -> tuple[int, ...]:
    return tuple(range(0, int(round(stop_s * 1e6)) + 1, step_us))


def _full_throttle(t: float) -> dict[str, float]:
    return {"throttle": 1.0}


def _abs_dry(t: float) -> dict[str, float]:
    return {"brake": 1.0 if t >= 0.2 else 0.0, "road_friction": 1.0}


def _low_friction(t: float) -> dict[str, float]:
    """Throttle on a wet road, brake onto snow, a short dry patch, throttle again on snow."""
    friction = 0.6 if t < 4.0 else (0.3 if t < 5.5 or t >= 6.0 else 1.0)
    if t < 3.5:
        return {"throttle": 0.45, "brake": 0.0, "road_friction": friction}
    if t < 7.0:
        return {"throttle": 0.0, "brake": 0.8, "road_friction": friction}
    return {"throttle": 0.7, "brake": 0.0, "road_friction": friction}


def _locked_on_slope(t: float) -> dict[str, float]:
    return {"brake": 1.0 if 0.5 <= t < 3.0 else 0.0, "throttle": 0.5 if t >= 3.5 else 0.0,
            "grade": -0.08 if t < 4.0 else 0.12, "road_friction": 0.8}


def _brake_pulses(t: float) -> dict[str, float]:
    return {"brake": 1.0 if (t % 1.0) < 0.45 else 0.2, "throttle": 0.0}


def _random_sequence(seed: int, stop_s: float) -> Sequence:
    """Inputs held for random spells, stepped through a random mix of communication steps."""
    rng = random.Random(seed)
    steps_us = (50, 300, 1000, 1000, 2500, 7000, 10000, 10000, 20000)
    points, t_us = [0], 0
    while t_us < stop_s * 1e6:
        t_us += rng.choice(steps_us)
        points.append(t_us)
    spells = []
    t = 0.0
    while t < stop_s:
        spells.append((t, {"throttle": rng.choice((0.0, 0.0, 0.4, 1.0)), "brake": rng.choice((0.0, 0.0, 0.3, 1.0)),
                           "road_friction": rng.choice((1.0, 1.0, 0.6, 0.3)),
                           "grade": rng.choice((0.0, 0.0, 0.05, -0.05))}))
        t += rng.uniform(0.2, 1.5)

    def schedule(now: float) -> dict[str, float]:
        return next(values for start, values in reversed(spells) if start <= now)

    return Sequence(tuple(points), schedule, {"v0": 15.0})


SEQUENCES: dict[str, Sequence] = {
    "full_throttle": Sequence(_even(12.0, 10000), _full_throttle),
    "abs_braking_dry": Sequence(_even(4.0, 1000), _abs_dry, {"v0": V100_MPS}),
    "low_friction": Sequence(_even(10.0, 5000), _low_friction, {"v0": 12.0}),
    "locked_wheels_on_slopes_rear_drive": Sequence(
        _even(7.0, 10000), _locked_on_slope, {"v0": 16.0, "abs_enabled": False, "drive_front_share": 0.3}),
    "fast_brake_release": Sequence(
        _even(4.0, 2500), _brake_pulses,
        {"v0": 25.0, "brake_release_dead_time_fraction": 0.2, "brake_release_time_constant_fraction": 1 / 3}),
    "random_inputs_random_steps": _random_sequence(seed=21, stop_s=8.0),
}


def run_sequence(fmu: Path, fmi_version: int, seq: Sequence, extra_inputs: dict[str, float] | None = None,
                 ) -> dict[str, np.ndarray]:
    """Run ``seq``; ``extra_inputs`` (such as the steering inputs held at 0) are set at every point."""
    extra = dict(extra_inputs or {})
    return run_plant_at(fmu, fmi_version, seq.points_us, lambda t: {**seq.schedule(t), **extra}, seq.params)


def stride(seq: Sequence) -> int:
    """Every how many communication points a row of values is stored."""
    mean_step_s = seq.points_us[-1] * 1e-6 / (len(seq.points_us) - 1)
    return max(1, int(round(STRIDE_S / mean_step_s)))


def digest(run: dict[str, np.ndarray]) -> str:
    """SHA-256 over the time column and every output, all rows, as little-endian float64."""
    h = hashlib.sha256()
    for name in ("t", *OUTPUTS):
        h.update(name.encode() + b"\0" + np.ascontiguousarray(run[name], dtype="<f8").tobytes())
    return h.hexdigest()


def record(fmu: Path) -> dict[str, dict]:
    """The golden data of every sequence from ``fmu`` (FMI 2)."""
    data = {}
    for name, seq in SEQUENCES.items():
        run = run_sequence(fmu, 2, seq)
        k = stride(seq)
        data[name] = {"rows": len(run["t"]), "stride": k, "sha256": digest(run),
                      **{col: [float(x).hex() for x in run[col][::k]] for col in ("t", *OUTPUTS)}}
    return data


def load_golden() -> dict[str, dict]:
    return json.loads(GOLDEN_PATH.read_text())["sequences"]


def main() -> None:
    import sys

    fmu = Path(sys.argv[1])
    payload = {"source": "FMI 2 build of commit d2cf42d (longitudinal-only plant)", "outputs": list(OUTPUTS),
               "sequences": record(fmu)}
    GOLDEN_PATH.write_text(json.dumps(payload, separators=(",", ":")) + "\n")


if __name__ == "__main__":
    main()
