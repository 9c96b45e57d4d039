"""False positives (crd): the number of interventions, goal 0, and no contact.

An intervention is any entry into a mode that limits the throttle or requests
braking after start-up (:func:`cosim.matrix.scoring.interventions`).
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from ..scoring import Outcome, ScoringDefaults, verdict_mark
from .tables import SourceTable


class FalsePositive(ScoringDefaults):
    name = "false_positive"
    table = SourceTable
    plots = ()  # no impacts to plot: the cells count interventions
    rule = ("PASS when the ECU never intervened (no throttle limit, no braking request after start-up) and "
            "there was no contact; the figure is the number of interventions, goal 0.")

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        ok = o.interventions == 0 and not o.collided
        return {"passed": ok, "verdict": "pass" if ok else f"FAIL ({o.interventions} interventions)"}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        """``PASS 0 interventions`` / ``**FAIL** 2 interventions, contact at 7.8 km/h``."""
        n = row["interventions"]
        text = f"{verdict_mark(row)} {n} intervention{'' if n == 1 else 's'}"
        return text + (f", contact at {row['impact_kmh']:.1f} km/h" if row["collided"] else "")

    def summary(self, rows: Sequence[Mapping[str, Any]], table: Any) -> str:
        return f"  interventions {sum(r['interventions'] for r in rows)}"


SCORING = FalsePositive()
