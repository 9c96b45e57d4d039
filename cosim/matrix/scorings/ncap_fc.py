"""Euro NCAP 2026 Crash Avoidance - Frontal Collisions v1.1 (Oct 2025), grid scoring of the planar scenarios.

A cell's KPI is the relative impact speed along the ego's heading (§5.2: the target's velocity along
it counts; a crossing target has none, so it is the ego's speed at impact). Its colour depends on
the ego's test speed (§5.3.1, Fig. 5-1; the band edges as in the official rating calculator
``Euro-NCAP/euroncap_rating_2026`` @94b1035, ``mitigation_or_avoidance_thresholds``, consistent with
the protocol's worked example at 60 km/h), see :data:`BANDS_BY_SPEED`:

* 10 and 20 km/h: green (no contact) or red;
* 30 km/h: green, brown up to 10 km/h, red above;
* 40 km/h: green, orange up to 10, brown up to 20, red above;
* 50 km/h and more: green, yellow up to 10, orange up to 20, brown up to 30, red above.

The turning and junction scenarios (:data:`AVOIDANCE_SCENARIOS`) are green without contact and red
with any (§5.2: their KPI is whether there was an impact). Sub-scores green 1.00, yellow 0.75, orange 0.50, brown
0.25, red 0. A scenario (a group's name up to its first ``-``: ``CPNA-25`` is CPNA) earns its
standard-range points times the mean sub-score of its standard cells, rounded to 0.01, plus its
extended points times the stepped share of its extended cells that are not red: 0 below 50 %,
0.5 from 50 %, 0.75 from 75 %, 1.0 at 100 % (§5.3.2). Robustness points need the verification
tests and are not scored here.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Sequence

from ecu.settings import Range, setting

from ..scoring import Outcome, ScoringDefaults, margin_text, no_contact_text

#: lowest test speed (km/h) -> the colour bands above green, (upper edge km/h, colour) each; above the last: red
BANDS_BY_SPEED: tuple[tuple[float, tuple[tuple[float, str], ...]], ...] = (
    (0.0, ()),
    (30.0, ((10.0, "brown"),)),
    (40.0, ((10.0, "orange"), (20.0, "brown"))),
    (50.0, ((10.0, "yellow"), (20.0, "orange"), (30.0, "brown"))),
)
#: scenarios whose KPI is contact or not (§5.2): turning across and crossing paths
AVOIDANCE_SCENARIOS = ("CCFtap", "CCCscp", "CMFtap", "CMCscp", "CPTA", "CBTA")
SUB_SCORES = {"green": 1.00, "yellow": 0.75, "orange": 0.50, "brown": 0.25, "red": 0.0}
#: (share of non-red extended cells at least, fraction of the extended points): §5.3.2's steps
EXTENDED_STEPS = ((1.0, 1.0), (0.75, 0.75), (0.5, 0.5))
#: the test speed is matched to a band row within this (km/h): the speeds are whole km/h
SPEED_TOL_KMH = 1e-6


@dataclass(frozen=True)
class NcapFcTable:
    """``[scoring]`` of an ``ncap_fc`` catalogue."""

    points: Mapping[str, float] = setting(factory=dict, allowed=Range(0.0, 100.0),
                                          doc="standard-range points per scenario (CPNA = 0.5)")
    extended_points: Mapping[str, float] = setting(factory=dict, allowed=Range(0.0, 100.0),
                                                   doc="extended-range points per scenario")
    source: str = setting("", doc="the key(s) of [sources] the points cite, joined by +")


def scenario_of(group: str) -> str:
    """The protocol scenario of a group: its name up to the first ``-`` (``CPNA-25`` -> ``CPNA``)."""
    return group.split("-", 1)[0]


def bands_at(test_speed_kmh: float) -> tuple[tuple[float, str], ...]:
    """The colour bands above green at a test speed (the row of the highest lowest speed not above it)."""
    row = BANDS_BY_SPEED[0][1]
    for low, bands in BANDS_BY_SPEED:
        if test_speed_kmh >= low - SPEED_TOL_KMH:
            row = bands
    return row


def fc_colour(test_speed_kmh: float, impact_kmh: float, collided: bool, avoidance: bool = False) -> str:
    """The colour of a cell: green without contact; with contact, the band of ``impact_kmh`` (red above)."""
    if not collided:
        return "green"
    if avoidance:
        return "red"
    return next((colour for edge, colour in bands_at(test_speed_kmh) if impact_kmh <= edge), "red")


def extended_fraction(share: float) -> float:
    """The fraction of the extended points earned by a share of non-red extended cells (§5.3.2)."""
    return next((frac for least, frac in EXTENDED_STEPS if share >= least - 1e-12), 0.0)


def scenario_points(rows: Sequence[Mapping[str, Any]], table: NcapFcTable) -> dict[str, float]:
    """Points per scenario of one strategy's rows, and ``total``."""
    cells: dict[str, tuple[list, list]] = {}
    for r in rows:
        if "colour" in r:
            cells.setdefault(scenario_of(r["group"]), ([], []))[1 if r.get("extended") else 0].append(r)
    out = {}
    for name, (std, ext) in cells.items():
        points = round(table.points.get(name, 0.0) * sum(SUB_SCORES[r["colour"]] for r in std) / len(std), 2) \
            if std else 0.0
        if ext:
            share = sum(r["colour"] != "red" for r in ext) / len(ext)
            points += table.extended_points.get(name, 0.0) * extended_fraction(share)
        out[name] = points
    out["total"] = sum(out.values())
    return out


class NcapFc(ScoringDefaults):
    name = "ncap_fc"
    table = NcapFcTable
    plots = ("bands",)
    rule = ("The colour of the relative impact speed along the ego's heading, with bands by test speed (Euro NCAP "
            "FC v1.1 Fig. 5-1): 10-20 km/h green or red; 30 km/h brown up to 10; 40 km/h orange up to 10, brown up "
            "to 20; from 50 km/h yellow up to 10, orange 20, brown 30; red above. Turning and junction scenarios: "
            "green without contact, red with any. A cell FAILs where it is not green (it loses points); ext = an "
            "extended-range cell (it scores unless red).")

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        avoid = scenario_of(params["group"]) in AVOIDANCE_SCENARIOS
        colour = fc_colour(float(params["ego_speed_kmh"]), o.impact_kmh, o.collided, avoid)
        extended = bool(params.get("extended"))
        return {"passed": colour == "green", "colour": colour, "score": SUB_SCORES[colour], "extended": extended,
                "verdict": colour + (" (extended)" if extended else "")}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        """``green no contact (min gap 1.2 m)`` / ``brown 17.3 km/h (2.7 under 20 km/h)``; ``ext`` on extended cells."""
        ext = " ext" if row.get("extended") else ""
        if not row["collided"]:
            return f"{row['colour']}{ext} {no_contact_text(row)}"
        edge = next((e for e, c in bands_at(row["test_speed_kmh"]) if c == row["colour"]), None)
        hit = f" on {row['hit_object']}" if row.get("hit_object") else ""
        margin = f" ({margin_text(row['impact_kmh'], edge, 'km/h')})" if edge is not None else ""
        return f"**{row['colour']}**{ext} {row['impact_kmh']:.1f} km/h{hit}{margin}"

    def summary(self, rows: Sequence[Mapping[str, Any]], table: NcapFcTable) -> str:
        """``bands: ...  NCAP 3.21/8.3 pts (CPNA 0.31, ...)`` of one strategy's rows."""
        pts = scenario_points(rows, table)
        counts = ", ".join(f"{sum(r.get('colour') == c for r in rows)} {c}" for c in SUB_SCORES)
        most = sum(table.points.values()) + sum(table.extended_points.values())
        errored = sum("colour" not in r for r in rows)
        unscored = f"  {errored} cells errored (not scored)" if errored else ""
        return f"  bands: {counts}  NCAP {pts['total']:.2f}/{most:.2f} pts (" + \
            ", ".join(f"{g} {v:.2f}" for g, v in pts.items() if g != "total") + ")" + unscored


SCORING = NcapFc()
