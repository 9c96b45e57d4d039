"""``crd animate`` on a 15 s run: wall and CPU time of the command, median of 3.

Run: ``python benchmarks/bench_animate.py [--gif]``. Makes the paper's scene cut to 15 s
(``crd run`` on paper_cyclist with ``duration_s = 15``), then times ``crd animate RUN_DIR``
(MP4, 1280x720 at 25 fps, and the PNG) as a separate process three times; prints each run
and the medians. The CPU time counts the command and its ffmpeg.
"""

from __future__ import annotations

import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from cosim.scenarios.loader import load_scenario  # noqa: F401 - fails early outside the project's venv

CRD = [str(Path(sys.executable).parent / "crd")]  # the installed command, as a user runs it


def _children_cpu_s() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def main() -> None:
    extra = sys.argv[1:]
    with tempfile.TemporaryDirectory() as tmp:
        toml = Path(tmp) / "paper15.toml"
        source = Path(__file__).resolve().parents[1] / "cosim" / "scenarios" / "paper_cyclist.toml"
        toml.write_text(source.read_text().replace("duration_s = 40.0", "duration_s = 15.0"))
        subprocess.run([*CRD, "run", str(toml), "--out", f"{tmp}/run"], check=True, capture_output=True)
        walls, cpus = [], []
        for i in range(3):
            cpu0, t0 = _children_cpu_s(), time.perf_counter()
            subprocess.run([*CRD, "animate", f"{tmp}/run", *extra], check=True, capture_output=True)
            walls.append(time.perf_counter() - t0)
            cpus.append(_children_cpu_s() - cpu0)
            print(f"run {i + 1}: wall {walls[-1]:.2f} s, CPU {cpus[-1]:.2f} s")
        print(f"median: wall {statistics.median(walls):.2f} s, CPU {statistics.median(cpus):.2f} s")


if __name__ == "__main__":
    main()
