"""Two written runs side by side (``crd compare``): their metrics' differences and speed profiles.

Runs pair by strategy, except that two directories of one run each pair those two runs
(:func:`paired`); when nothing pairs, :func:`differences` says so instead of a verdict.

The directories are read by :mod:`cosim.results.run_dir`. Differences are rounded
as in ``report.md`` (:mod:`cosim.results.report`).
"""

from __future__ import annotations

from ..errors import ConfigError
from .report import fmt
from .run_dir import RunDir
from .run_record import RunRecord

#: metric key -> (label, decimals; None for a yes/no)
METRICS = {
    "collided": ("collided", None),
    "impact_speed_mps": ("impact speed (m/s)", 2),
    "min_gap_m": ("min gap (m)", 2),
    "final_gap_m": ("final gap (m)", 2),
    "contingency_invocations": ("contingency invocations", 0),
    "max_speed_mps": ("max speed (m/s)", 2),
    "sim_time_s": ("simulated time (s)", 2),
    "wall_time_s": ("wall time (s)", 2),
}


def _value(key: str, value) -> str:
    digits = METRICS[key][1]
    if digits is None:
        return "yes" if value else "no"
    return fmt(value, digits)


def _delta(key: str, a, b) -> str:
    """B − A of the rounded values; blank when they are equal."""
    digits = METRICS[key][1]
    if _value(key, a) == _value(key, b):
        return ""
    if digits is None or a is None or b is None:
        return "differs"
    return f"{round(b, digits) - round(a, digits):+.{digits}f}"


def paired(a: RunDir, b: RunDir) -> tuple[list[tuple[RunRecord, RunRecord]], list[str], list[str]]:
    """The runs to compare, and the strategies left unpaired in A and in B.

    Two directories of one run each pair those runs, whatever their strategies (``crd run
    --strategy tightening`` against ``--strategy none``); otherwise runs pair by strategy.
    """
    if len(a.records) == 1 and len(b.records) == 1:
        return [(a.records[0], b.records[0])], [], []
    by_b = {r.strategy: r for r in b.records}
    pairs = [(r, by_b[r.strategy]) for r in a.records if r.strategy in by_b]
    in_a = {r.strategy for r in a.records}
    return (pairs, [r.strategy for r in a.records if r.strategy not in by_b],
            [r.strategy for r in b.records if r.strategy not in in_a])


def _label(ra: RunRecord, rb: RunRecord) -> str:
    return ra.strategy if ra.strategy == rb.strategy else f"{ra.strategy} | {rb.strategy}"


def differences(a: RunDir, b: RunDir) -> list[str]:
    """Lines of a table: every metric of every pair of runs (:func:`paired`), A, B and B − A.

    Raises :class:`ConfigError` when no run pairs with another: nothing compared is never "identical".
    """
    pairs, only_a, only_b = paired(a, b)
    if not pairs:
        held = [f"{d.path} holds {', '.join(r.strategy for r in d.records) or 'no run'}" for d in (a, b)]
        raise ConfigError(f"nothing to compare: {held[0]}; {held[1]} (runs pair by strategy, or one run with one)")
    width = max(len("strategy"), *(len(_label(ra, rb)) for ra, rb in pairs))
    lines = [f"A = {a.path}", f"B = {b.path}", "",
             f"{'strategy':<{width}} {'metric':<24} {'A':>9} {'B':>9} {'B - A':>9}"]
    lines.append("-" * len(lines[-1]))
    changed, compared = 0, 0
    for ra, rb in pairs:
        ma, mb = ra.metrics.as_dict(), rb.metrics.as_dict()
        for key, (label, _) in METRICS.items():
            va, vb = ma[key], mb[key]
            if key != "wall_time_s":
                compared += 1
                changed += _value(key, va) != _value(key, vb)
            lines.append(f"{_label(ra, rb) if key == 'collided' else '':<{width}} {label:<24} {_value(key, va):>9}"
                         f" {_value(key, vb):>9} {_delta(key, va, vb):>9}")
    lines += [f"only in {name}: {', '.join(only)}" for name, only in (("A", only_a), ("B", only_b)) if only]
    lines.append(f"{changed} of {compared} metrics differ (wall time aside)" if changed
                 else f"identical in all {compared} metrics (wall time aside)")
    return lines
