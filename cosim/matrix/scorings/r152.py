"""UN R152, para. 5.2.1.4 (table for M1): pass iff the relative impact speed is at most the cell's limit.

A cell's ``max_impact_kmh`` is the limit; 0 means no contact is allowed.
"""

from __future__ import annotations

from typing import Any, Mapping

from ..scoring import Outcome, ScoringDefaults, fail_mark, impact_text
from .tables import SourceTable


class R152(ScoringDefaults):
    name = "r152"
    table = SourceTable
    plots = ("impact",)
    limit_header = "limit km/h"
    required_keys = ("max_impact_kmh",)

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        limit = float(params["max_impact_kmh"])
        ok = (not o.collided) if limit == 0.0 else (not o.collided or o.impact_kmh <= limit)
        return {"passed": ok, "verdict": "pass" if ok else f"FAIL (limit {limit:g} km/h)"}

    def row_fields(self, params: Mapping[str, Any]) -> dict[str, Any]:
        return {"max_impact_kmh": float(params.get("max_impact_kmh"))}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        return impact_text(row) + fail_mark(row)

    def limit_text(self, row: Mapping[str, Any]) -> str:
        return f"{row['max_impact_kmh']:g}"


SCORING = R152()
