"""UN R152, para. 5.2.1.4 (table for M1): pass iff the relative impact speed is at most the cell's limit.

A cell's ``max_impact_kmh`` is the limit; 0 means no contact is allowed.
"""

from __future__ import annotations

from typing import Any, Mapping

from ..scoring import Outcome, ScoringDefaults, margin_text, no_contact_text, verdict_mark
from .tables import SourceTable


class R152(ScoringDefaults):
    name = "r152"
    table = SourceTable
    plots = ("impact",)
    limit_header = "limit km/h"
    required_keys = ("max_impact_kmh",)
    rule = ("PASS when the relative impact speed is at most the cell's limit (limit 0: no contact allowed); "
            "the margin is the distance to the limit in km/h, or the smallest gap without contact.")

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        limit = float(params["max_impact_kmh"])
        ok = (not o.collided) if limit == 0.0 else (not o.collided or o.impact_kmh <= limit)
        return {"passed": ok, "verdict": "pass" if ok else f"FAIL (limit {limit:g} km/h)"}

    def row_fields(self, params: Mapping[str, Any]) -> dict[str, Any]:
        return {"max_impact_kmh": float(params.get("max_impact_kmh"))}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        """``PASS no contact (min gap 2.6 m)`` / ``PASS 7.9 km/h (27.1 under 35 km/h)`` / ``**FAIL** 7.5 km/h
        (7.5 over 0 km/h)``."""
        if not row["collided"]:
            return f"{verdict_mark(row)} {no_contact_text(row)}"
        impact = row["impact_kmh"]
        return f"{verdict_mark(row)} {impact:.1f} km/h ({margin_text(impact, row['max_impact_kmh'], 'km/h')})"

    def limit_text(self, row: Mapping[str, Any]) -> str:
        return f"{row['max_impact_kmh']:g}"


SCORING = R152()
