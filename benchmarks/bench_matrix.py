"""Wall time of the protocol catalogues: R152 + Euro NCAP + false positives, three strategies.

Goal (issue 11): the whole R152 + NCAP + false-positive run on 2 cores in <= 3 min at 1 phase.
Prints the wall time with 1 and with 2 workers side by side (their ratio is the pool's
speed-up on this host), the runs per second, and the simulated-to-wall ratio of the runs.

Run: python benchmarks/bench_matrix.py [--phases N] [--catalogues a,b,c]
"""

from __future__ import annotations

import argparse
import os

from cosim.matrix.catalogue import load_catalogue
from cosim.matrix.runner import run_matrix

STRATEGIES = ["none", "conservative", "tightening"]


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--phases", type=int, default=1)
    ap.add_argument("--catalogues", default="r152_m1,ncap_ccr,false_positive")
    ap.add_argument("--workers", default="1,2", help="comma-separated worker counts to compare")
    args = ap.parse_args()
    cats = [load_catalogue(c) for c in args.catalogues.split(",")]
    print(f"host: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f}")
    for workers in (int(w) for w in args.workers.split(",")):
        rows, wall_s = run_matrix(cats, STRATEGIES, args.phases, workers)
        sim_s = sum(r["sim_time_s"] * r["phases"] for r in rows)
        runs = len(rows) * args.phases
        print(f"{workers} worker(s): {runs} runs in {wall_s:6.1f} s  ({runs / wall_s:5.2f} runs/s,"
              f" {sim_s:.0f} s simulated, {sim_s / wall_s:5.1f}x real time)  goal <= 180 s")


if __name__ == "__main__":
    main()
