"""Euro NCAP 2026 Crash Avoidance - Frontal Collisions v1.1, scoring.

The relative impact speed sets a colour: green (no contact) 1.00, yellow
(0, 10] km/h 0.75, orange (10, 20] 0.50, brown (20, 30] 0.25, red > 30 km/h 0
(the protocol's worked example); an extended-range cell scores 1.0 unless red.
A group scores ``points * mean(cell scores)`` (equal cell weights: our
assumption, the protocol weights are not in our sources). Requirement: a cell
with ``require_no_contact`` (CCRs <= 20 km/h) must be green.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable, Mapping, Sequence

from ecu.settings import Range, setting

from ..scoring import Outcome, ScoringDefaults, margin_text, no_contact_text

#: (upper edge of relative impact speed in km/h, colour, sub-score); above the last edge: red.
NCAP_BANDS: tuple[tuple[float, str, float], ...] = (
    (0.0, "green", 1.00), (10.0, "yellow", 0.75), (20.0, "orange", 0.50), (30.0, "brown", 0.25))
RED = ("red", 0.0)


@dataclass(frozen=True)
class NcapTable:
    """``[scoring]`` of an ``ncap`` catalogue."""

    points: Mapping[str, float] = setting(factory=dict, allowed=Range(0.0, 100.0),
                                          doc="points per group (the series' group names), e.g. CCRs = 1.2")
    source: str = setting("", doc="the key(s) of [sources] the points cite, joined by +")


def ncap_colour(impact_kmh: float, collided: bool) -> tuple[str, float]:
    """Colour and sub-score of a standard cell."""
    if not collided:
        return NCAP_BANDS[0][1], NCAP_BANDS[0][2]
    for edge, colour, score in NCAP_BANDS[1:]:
        if impact_kmh <= edge:
            return colour, score
    return RED


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


class Ncap(ScoringDefaults):
    name = "ncap"
    table = NcapTable
    plots = ("impact", "bands")
    rule = ("The colour band of the relative impact speed: green no contact, yellow up to 10 km/h, orange up "
            "to 20, brown up to 30, red above 30; the margin is the distance to the band's upper edge. FAIL "
            "only where the protocol requires avoidance (CCRs up to 20 km/h); the other cells have no "
            "pass mark, only points.")

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        colour, score = ncap_colour(o.impact_kmh, o.collided)
        if params.get("extended") and colour != "red":
            score = 1.0
        ok = not (params.get("require_no_contact") and o.collided)
        return {"passed": ok, "colour": colour, "score": score,
                "verdict": colour if ok else f"FAIL ({colour}; avoidance required)"}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        """``green no contact (min gap 1.2 m)`` / ``yellow 5.7 km/h (4.3 under 10 km/h)`` / ``red 39.7 km/h
        (9.7 over 30 km/h)``; ``**FAIL** (avoidance required)`` first where the cell requires avoidance."""
        fail = "" if row["passed"] else "**FAIL** (avoidance required) "
        if not row["collided"]:
            return f"{fail}{row['colour']} {no_contact_text(row)}"
        impact = row["impact_kmh"]
        edge = next((e for e, colour, _ in NCAP_BANDS[1:] if colour == row["colour"]), NCAP_BANDS[-1][0])
        return f"{fail}{row['colour']} {impact:.1f} km/h ({margin_text(impact, edge, 'km/h')})"

    def summary(self, rows: Sequence[Mapping[str, Any]], table: NcapTable) -> str:
        """``NCAP total/max pts (per group)`` of one strategy's rows."""
        by_strategy = ncap_points(rows, table.points)
        if not by_strategy:
            return ""
        (p,) = by_strategy.values()
        bands = [colour for _, colour, _ in NCAP_BANDS] + [RED[0]]
        counts = ", ".join(f"{sum(r.get('colour') == c for r in rows)} {c}" for c in bands)
        return f"  bands: {counts}  NCAP {p['total']:.2f}/{sum(table.points.values()):.1f} pts (" + \
            ", ".join(f"{g} {v:.2f}" for g, v in p.items() if g != "total") + ")"


SCORING = Ncap()
