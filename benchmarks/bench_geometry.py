"""Box overlap: our separating-axis test against shapely 2, for one pair and for one box against 8 and 64.

Run: ``python benchmarks/bench_geometry.py`` (needs shapely, a test dependency). Alternating, 9 rounds,
medians in microseconds per call and the ratio shapely / ours. Both sides start from the boxes' poses
(x, y, yaw, length, width): shapely's polygons are built from the corners, as a loop would have to.
"""

from __future__ import annotations

import timeit

import numpy as np
import shapely

from cosim.world.geometry import Box, overlaps, overlaps_many

EGO = Box(0.0, 0.0, 0.1, 4.5, 1.8)
PAIR = Box(3.0, 1.0, 0.7, 4.0, 1.7)
NEAR8 = np.array([(3.0 + 1.0 * i, 1.0 - 0.3 * i, 0.3 * i, 4.0, 1.7) for i in range(8)])  # all 8 near the ego
SPREAD8 = np.array([(3.0 + 12.0 * i, 1.0 - 0.3 * i, 0.3 * i, 4.0, 1.7) for i in range(8)])  # 1 near, 7 far
_RNG = np.random.default_rng(3)
MANY64 = np.column_stack([_RNG.uniform(-60, 60, 64), _RNG.uniform(-10, 10, 64), _RNG.uniform(-3, 3, 64),
                          _RNG.uniform(0.5, 5, 64), _RNG.uniform(0.5, 2, 64)])
_SX, _SY = np.array([1, -1, -1, 1]), np.array([1, 1, -1, -1])


def shapely_many(rows: np.ndarray) -> np.ndarray:
    """shapely 2, vectorised: the corners in numpy, one ``polygons`` and one ``intersects`` call."""
    c, s = np.cos(rows[:, 2:3]), np.sin(rows[:, 2:3])
    hl, hw = rows[:, 3:4] / 2, rows[:, 4:5] / 2
    x = rows[:, 0:1] + _SX * hl * c - _SY * hw * s
    y = rows[:, 1:2] + _SX * hl * s + _SY * hw * c
    return shapely.intersects(shapely.Polygon(EGO.corners()), shapely.polygons(np.stack([x, y], axis=-1)))


def shapely_pair() -> bool:
    return shapely.Polygon(EGO.corners()).intersects(shapely.Polygon(PAIR.corners()))


CASES = {
    "pair": (lambda: overlaps(EGO, PAIR), shapely_pair, 2000),
    "8 near": (lambda: overlaps_many(EGO, NEAR8), lambda: shapely_many(NEAR8), 1000),
    "8 spread": (lambda: overlaps_many(EGO, SPREAD8), lambda: shapely_many(SPREAD8), 1000),
    "64": (lambda: overlaps_many(EGO, MANY64), lambda: shapely_many(MANY64), 300),
}


def main() -> None:
    for rows in (NEAR8, SPREAD8, MANY64):
        assert list(shapely_many(rows)) == list(overlaps_many(EGO, rows))
    times = {(case, side): [] for case in CASES for side in ("sat", "shapely")}
    for _ in range(9):
        for case, (ours, theirs, n) in CASES.items():
            times[case, "sat"].append(timeit.timeit(ours, number=n) / n * 1e6)
            times[case, "shapely"].append(timeit.timeit(theirs, number=n) / n * 1e6)
    print("| boxes | separating axes (us) | shapely 2 (us) | shapely / ours |\n|---|---|---|---|")
    for case in CASES:
        a, b = np.median(times[case, "sat"]), np.median(times[case, "shapely"])
        print(f"| {case} | {a:.1f} | {b:.1f} | {b / a:.1f} |")


if __name__ == "__main__":
    main()
