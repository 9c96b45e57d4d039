"""The claims of Johnson (2019), section III, as checks on the three runs.

1. ``none`` collides with the cyclist.
2. ``conservative`` and ``tightening`` stop short of it.
3. ``none`` and ``conservative`` show the reciprocal dance: at least 3
   separate contingency invocations each.
4. ``tightening`` holds a higher speed than ``conservative`` over part of the
   constrained approach before 200 m, and a lower speed from 200 m to the cyclist.
5. ``tightening`` ends farther from the cyclist than ``conservative``.

Claim 4 compares *first-pass* speed profiles v(p): the speed when the car
first reaches position p (the car never reverses; a stopped car has v = 0 at
every position it has not reached). On a 0.25 m grid:

* 4a: the constrained approach starts where either run first leaves STANDBY;
  between there and 200 m, ``tightening`` is faster than ``conservative`` by
  more than ``SPEED_MARGIN_MPS`` over a contiguous stretch of at least
  ``MIN_STRETCH_M``;
* 4b: from 200 m to the farthest position either car reaches, ``tightening``
  is slower than ``conservative`` at ``MIN_SLOWER_FRACTION`` of the grid points.

The thresholds are ours (the paper reads them off a figure); they are stated
with each result.

Claim 3 judged from the speed trace (issue 14): :func:`speed_trace_dance`
counts separate decelerations with recoveries in between from
``timeseries.csv``'s speed (:mod:`cosim.results.speed_dance`), not from the
ECU's count. It is reported beside the five claims and does **not** hold in
our co-simulation yet (README, "The dance in the speed trace"), so it does not
set ``crd paper``'s exit code.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..scenarios.config import PAPER_STRATEGIES
from .report import Verdict, fmt
from .run_record import RunRecord
from .speed_dance import DROP_MPS, RISE_MPS, speed_dance

#: the runs the claims need: one per strategy of the paper (the one list, ``PAPER_STRATEGIES``)
REQUIRED = PAPER_STRATEGIES
SPLIT_POSITION_M = 200.0
GRID_M = 0.25
SPEED_MARGIN_MPS = 0.1
MIN_STRETCH_M = 5.0
MIN_SLOWER_FRACTION = 0.9
DANCE_MIN_INVOCATIONS = 3
DANCE_MIN_DECELERATIONS = 3


@dataclass(frozen=True)
class Claim:
    number: str
    text: str
    passed: bool
    detail: str


def first_pass_speed(record: RunRecord, positions_m: np.ndarray) -> np.ndarray:
    """Speed (m/s) when the car first reaches each position; 0 beyond the farthest reached."""
    pos = np.maximum.accumulate(np.asarray(record.column("position_m"), dtype=float))
    speed = np.asarray(record.column("speed_mps"), dtype=float)
    idx = np.searchsorted(pos, positions_m, side="left")
    out = np.zeros_like(positions_m)
    reached = idx < len(pos)
    out[reached] = speed[idx[reached]]
    return out


def _first_constrained_position(record: RunRecord) -> float:
    for pos, mode in zip(record.column("position_m"), record.column("ecu_mode")):
        if mode not in ("STANDBY", "NO_OVERRIDE"):
            return pos
    return float("inf")


def _longest_run(mask: np.ndarray) -> int:
    best = cur = 0
    for m in mask:
        cur = cur + 1 if m else 0
        best = max(best, cur)
    return best


def _claim4(cons: RunRecord, tight: RunRecord) -> Claim:
    start = min(_first_constrained_position(cons), _first_constrained_position(tight))
    text = "tightening faster than conservative over part of the approach before 200 m, slower from 200 m on"
    if not start < SPLIT_POSITION_M:
        return Claim("4", text, False, f"no constrained approach before {SPLIT_POSITION_M} m (starts at {start:.1f} m)")
    before = np.arange(start, SPLIT_POSITION_M, GRID_M)
    faster = first_pass_speed(tight, before) - first_pass_speed(cons, before) > SPEED_MARGIN_MPS
    stretch_m = _longest_run(faster) * GRID_M
    end = max(max(cons.column("position_m")), max(tight.column("position_m")))
    after = np.arange(SPLIT_POSITION_M, max(end, SPLIT_POSITION_M + GRID_M), GRID_M)
    slower = first_pass_speed(tight, after) < first_pass_speed(cons, after)
    frac = float(slower.mean())
    ok = stretch_m >= MIN_STRETCH_M and frac >= MIN_SLOWER_FRACTION
    detail = (f"faster by >{SPEED_MARGIN_MPS} m/s over {stretch_m:.1f} m of {start:.1f}..{SPLIT_POSITION_M:.0f} m"
              f" (need >= {MIN_STRETCH_M} m); slower at {frac:.0%} of {SPLIT_POSITION_M:.0f}..{end:.1f} m"
              f" (need >= {MIN_SLOWER_FRACTION:.0%})")
    return Claim("4", text, ok, detail)


def evaluate(records: list[RunRecord]) -> list[Claim]:
    """The five claims on runs named ``none``, ``conservative`` and ``tightening``."""
    by = {r.strategy: r for r in records}
    missing = [s for s in REQUIRED if s not in by]
    if missing:
        raise KeyError(f"paper claims need runs {list(REQUIRED)}, missing {missing}")
    none, cons, tight = (by[s].metrics for s in REQUIRED)
    inv = {s: by[s].metrics.contingency_invocations for s in REQUIRED}
    return [
        Claim("1", "none collides with the cyclist", none.collided,
              f"collided={none.collided}, impact {fmt(none.impact_speed_mps, unit='m/s')}"),
        Claim("2", "conservative and tightening stop short of the cyclist",
              not cons.collided and not tight.collided,
              f"conservative collided={cons.collided}, final gap {fmt(cons.final_gap_m, unit='m')}; "
              f"tightening collided={tight.collided}, final gap {fmt(tight.final_gap_m, unit='m')}"),
        Claim("3", f"none and conservative dance: >= {DANCE_MIN_INVOCATIONS} contingency invocations each",
              inv["none"] >= DANCE_MIN_INVOCATIONS and inv["conservative"] >= DANCE_MIN_INVOCATIONS,
              f"invocations: none {inv['none']}, conservative {inv['conservative']} (tightening {inv['tightening']})"),
        _claim4(by["conservative"], by["tightening"]),
        Claim("5", "tightening ends farther from the cyclist than conservative",
              cons.final_gap_m is not None and tight.final_gap_m is not None and tight.final_gap_m > cons.final_gap_m,
              f"final gap: tightening {fmt(tight.final_gap_m, unit='m')},"
              f" conservative {fmt(cons.final_gap_m, unit='m')}"),
    ]


def speed_trace_dance(records: list[RunRecord]) -> Claim:
    """Claim 3 from the speed trace: ``none`` and ``conservative`` each show >= 3 separate decelerations."""
    by = {r.strategy: r for r in records}
    found = {s: speed_dance(by[s].column("speed_mps")) for s in ("none", "conservative") if s in by}
    ok = len(found) == 2 and all(d.decelerations >= DANCE_MIN_DECELERATIONS for d in found.values())
    detail = "; ".join(f"{s}: {d.decelerations} deceleration(s), largest recovery "
                       f"{max(d.rises_mps, default=0.0):.2f} m/s" for s, d in found.items())
    return Claim("3s", f"speed trace: none and conservative show >= {DANCE_MIN_DECELERATIONS} separate decelerations"
                 f" (falls >= {DROP_MPS} m/s, recoveries >= {RISE_MPS} m/s between)", ok, detail)


def verdicts(records: list[RunRecord]) -> tuple[str, list[Verdict]]:
    """The claims for ``report.md``."""
    trace = speed_trace_dance(records)
    return "The paper's claims", [Verdict(f"claim {c.number}: {c.text}", c.passed, c.detail)
                                  for c in evaluate(records)] + [
        Verdict(f"claim {trace.number} (reported, issue 14; not part of the exit code): {trace.text}",
                trace.passed, trace.detail)]
