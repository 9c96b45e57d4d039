"""Progress on stderr and the closing table (CLI only prints)."""

from __future__ import annotations

import sys
from typing import Callable

from ..results.run_record import RunRecord


def progress_printer(strategy: str) -> Callable[[float, float], None]:
    """A progress callback on stderr: ``strategy  t / duration s``.

    On a terminal one line is rewritten in place; otherwise (a log file, CI) a
    line is written every 10 s of simulated time and at the end, never a
    carriage-return soup.
    """
    stream = sys.stderr
    interactive = stream.isatty()
    last = [-10.0]

    def show(t_s: float, duration_s: float) -> None:
        done = t_s >= duration_s
        if interactive:
            stream.write(f"\r  {strategy:<13} {t_s:6.1f} / {duration_s:.1f} s sim" + ("\n" if done else ""))
        elif t_s != last[0] and (done or t_s - last[0] >= 10.0):
            last[0] = t_s
            stream.write(f"  {strategy:<13} {t_s:6.1f} / {duration_s:.1f} s sim\n")
        stream.flush()

    return show


def end_progress() -> None:
    sys.stderr.flush()


def _fmt(x, spec: str) -> str:
    return "-" if x is None else format(x, spec)


def results_table(records: list[RunRecord], wall: bool = True) -> str:
    """The closing table of ``crd run``/``crd paper``; ``wall=False`` leaves out the one machine-dependent
    column, the wall time (for the documentation's copy)."""
    head = f"{'strategy':<13} {'collided':>8} {'impact m/s':>10} {'min gap m':>9} {'final gap m':>11} " \
           f"{'conting.':>8} {'max v m/s':>9} {'sim s':>6}" + (f" {'wall s':>6}" if wall else "")
    lines = [head, "-" * len(head)]
    for r in records:
        m = r.metrics
        lines.append(f"{m.strategy:<13} {str(m.collided):>8} {_fmt(m.impact_speed_mps, '10.2f')} "
                     f"{_fmt(m.min_gap_m, '9.2f')} {_fmt(m.final_gap_m, '11.2f')} {m.contingency_invocations:>8d} "
                     f"{m.max_speed_mps:9.2f} {m.sim_time_s:6.2f}" + (f" {m.wall_time_s:6.2f}" if wall else "")
                     + (f"  ERROR: {r.error}" if r.error else ""))
    return "\n".join(lines)
