"""Where ``crd paper``'s time goes: a timeline of its phases in every process (issue 20's breakdown).

Run: ``python benchmarks/paper_phases.py [--out DIR]`` (from the tree to measure, with its venv). It runs
``crd paper`` in this process through :func:`cosim.cli.main.main` as the ``crd`` command does, with the
project's own phase functions wrapped to print, as each begins and ends, the wall time since this script
started, the process and that process's CPU time. The phases: imports, the runs (in the workers),
matplotlib's import, each timeline, the speed profiles (in the plot process), the report, and the exit
(after ``main`` returns, the interpreter's shutdown; ``CPU total`` counts every process). Wrapping costs
microseconds per call; the phases are those of a plain ``crd paper``.
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time

T0 = time.perf_counter()


def _event(name: str) -> None:
    print(f"{time.perf_counter() - T0:6.2f} s  pid {os.getpid():>7}  cpu {time.process_time():5.2f} s  {name}",
          file=sys.stderr, flush=True)


def _wrapped(module, name: str):
    inner = getattr(module, name)

    def phase(*args, **kwargs):
        _event(f"{name} begins")
        try:
            return inner(*args, **kwargs)
        finally:
            _event(f"{name} ends")

    phase.__qualname__ = phase.__name__ = f"phase_{name}"
    return phase


def phase_speed_profiles(*args, **kwargs):  # module level: the plot process gets it pickled by name
    _event("speed_profiles begins")
    try:
        return _SPEED_PROFILES(*args, **kwargs)
    finally:
        _event("speed_profiles ends")


def main() -> None:
    global _SPEED_PROFILES
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", help="output directory (default: a temporary one)")
    args = parser.parse_args()
    out = args.out or tempfile.mkdtemp(prefix="paper_phases_")
    sys.modules.setdefault("asammdf", None)  # as the crd command does (cosim.cli.main)
    _event("python up")
    import cosim.loop.experiment as experiment
    import cosim.results.plots as plots
    from cosim.cli import main as cli

    _event("crd's run and plot modules imported")
    for name in ("_run_one", "preload_matplotlib", "timeline", "write_report", "run_concurrently"):
        setattr(experiment, name, _wrapped(experiment, name))
    _SPEED_PROFILES = plots.speed_profiles
    experiment.speed_profiles = phase_speed_profiles
    sys.argv = ["crd", "paper", "--out", out]
    code = cli.main()
    _event(f"crd paper returned {code}; the exit follows")
    usage = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    print(f"CPU so far: this process {usage[0].ru_utime + usage[0].ru_stime:.2f} s, "
          f"its workers {usage[1].ru_utime + usage[1].ru_stime:.2f} s", file=sys.stderr)


_SPEED_PROFILES = None

if __name__ == "__main__":
    main()
