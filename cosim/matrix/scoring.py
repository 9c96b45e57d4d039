"""Scoring a cell's outcome as its protocol does.

* ``r152`` (UN R152, para. 5.2.1.4 table for M1): pass iff the relative impact
  speed is at most the cell's ``max_impact_kmh`` (0: no contact allowed).
* ``ncap`` (Euro NCAP 2026 Crash Avoidance - Frontal Collisions v1.1, scoring):
  the relative impact speed sets a colour, green (no contact) 1.00, yellow
  (0, 10] km/h 0.75, orange (10, 20] 0.50, brown (20, 30] 0.25, red > 30 km/h
  0 (the protocol's worked example); an extended-range cell scores 1.0 unless
  red. A group scores ``points * mean(cell scores)`` (equal cell weights: our
  assumption, the protocol weights are not in our sources). Requirement: a
  cell with ``require_no_contact`` (CCRs <= 20 km/h) must be green.
* ``false_positive``: the number of interventions, where an intervention is
  any entry into a mode that limits the throttle or requests braking after
  start-up; goal 0 and no contact.
* ``follow`` (ours): behind a moving target the ECU brakes to zero relative
  speed and must not bring the car to a standstill: pass iff no contact and
  the minimum speed from the first intervention until 1 s after the last
  stays above 1 m/s (:func:`cosim.matrix.runner.outcome_of`).

With several radar phases a cell is scored on its worst phase: the highest
impact speed, the most interventions, the lowest speed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable, Mapping, Sequence

#: (upper edge of relative impact speed in km/h, colour, sub-score); above the last edge: red.
NCAP_BANDS: tuple[tuple[float, str, float], ...] = (
    (0.0, "green", 1.00), (10.0, "yellow", 0.75), (20.0, "orange", 0.50), (30.0, "brown", 0.25))
RED = ("red", 0.0)
RESTRICTING_MODES = ("TIGHTENING", "CONTINGENCY")
FOLLOW_MIN_SPEED_MPS = 1.0
KMH = 3.6


@dataclass(frozen=True)
class Outcome:
    """What one run of one cell at one phase produced (plain data, crosses process boundaries)."""

    collided: bool
    impact_kmh: float
    interventions: int
    min_speed_intervening_mps: float | None
    min_gap_m: float | None
    end_reason: str | None
    sim_time_s: float
    wall_time_s: float
    error: str | None = None


def interventions(modes: Sequence[str]) -> int:
    """Entries into a restricting mode (or a FAULT after start-up) in the per-cycle ECU modes."""
    count, started, prev = 0, False, None
    for mode in modes:
        if mode == "STANDBY":
            started = True
        entering = mode != prev
        if entering and (mode in RESTRICTING_MODES or (started and mode == "FAULT")):
            count += 1
        prev = mode
    return count


def ncap_colour(impact_kmh: float, collided: bool) -> tuple[str, float]:
    """Colour and sub-score of a standard cell."""
    if not collided:
        return NCAP_BANDS[0][1], NCAP_BANDS[0][2]
    for edge, colour, score in NCAP_BANDS[1:]:
        if impact_kmh <= edge:
            return colour, score
    return RED


def worst(outcomes: Iterable[Outcome]) -> Outcome:
    """The worst phase: an error first, then contact at the highest speed, most interventions, lowest speed."""
    def badness(o: Outcome) -> tuple:
        low = o.min_speed_intervening_mps
        return (o.error is not None, o.collided, o.impact_kmh, o.interventions, -(low if low is not None else 1e9))
    return max(outcomes, key=badness)


def score_cell(scoring: str, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
    """The protocol's verdict on one cell: ``passed`` (requirement met), and colour/score for NCAP."""
    if o.error is not None:
        return {"passed": False, "verdict": f"error: {o.error}"}
    if scoring == "r152":
        limit = float(params["max_impact_kmh"])
        ok = (not o.collided) if limit == 0.0 else (not o.collided or o.impact_kmh <= limit)
        return {"passed": ok, "verdict": "pass" if ok else f"FAIL (limit {limit:g} km/h)"}
    if scoring == "ncap":
        colour, score = ncap_colour(o.impact_kmh, o.collided)
        if params.get("extended") and colour != "red":
            score = 1.0
        ok = not (params.get("require_no_contact") and o.collided)
        return {"passed": ok, "colour": colour, "score": score,
                "verdict": colour if ok else f"FAIL ({colour}; avoidance required)"}
    if scoring == "false_positive":
        ok = o.interventions == 0 and not o.collided
        return {"passed": ok, "verdict": "pass" if ok else f"FAIL ({o.interventions} interventions)"}
    low = o.min_speed_intervening_mps
    ok = not o.collided and (low is None or low > FOLLOW_MIN_SPEED_MPS)
    return {"passed": ok, "verdict": "pass" if ok else "FAIL (contact or standstill)"}


def ncap_points(rows: Iterable[Mapping[str, Any]], points: Mapping[str, float]) -> dict[str, dict[str, float]]:
    """Per strategy and group: ``points * mean(score)``, and ``total``."""
    acc: dict[str, dict[str, list[float]]] = {}
    for r in rows:
        if "score" in r and r["group"] in points:
            acc.setdefault(r["strategy"], {}).setdefault(r["group"], []).append(r["score"])
    out: dict[str, dict[str, float]] = {}
    for strategy, groups in acc.items():
        out[strategy] = {g: points[g] * sum(s) / len(s) for g, s in groups.items()}
        out[strategy]["total"] = sum(out[strategy].values())
    return out
