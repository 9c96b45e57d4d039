"""False positives (crd): the number of interventions, goal 0, and no contact.

An intervention is any entry into a mode that limits the throttle or requests
braking after start-up (:func:`cosim.matrix.scoring.interventions`).
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from ..scoring import Outcome, ScoringDefaults
from .tables import SourceTable


class FalsePositive(ScoringDefaults):
    name = "false_positive"
    table = SourceTable
    plots = ()  # no impacts to plot: the cells count interventions

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        ok = o.interventions == 0 and not o.collided
        return {"passed": ok, "verdict": "pass" if ok else f"FAIL ({o.interventions} interventions)"}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        return f"{row['interventions']} int." + (" HIT" if row["collided"] else "")

    def summary(self, rows: Sequence[Mapping[str, Any]], table: Any) -> str:
        return f"  interventions {sum(r['interventions'] for r in rows)}"


SCORING = FalsePositive()
