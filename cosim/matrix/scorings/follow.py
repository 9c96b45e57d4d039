"""Following a slower target (crd): the ECU brakes to zero relative speed and must not stop the car.

Pass iff no contact and the minimum speed from the first intervention until
1 s after the last stays above ``FOLLOW_MIN_SPEED_MPS``
(:func:`cosim.matrix.runner.outcome_of`).
"""

from __future__ import annotations

from typing import Any, Mapping

from ..scoring import Outcome, ScoringDefaults, margin_text, verdict_mark
from .tables import SourceTable

FOLLOW_MIN_SPEED_MPS = 1.0


class Follow(ScoringDefaults):
    name = "follow"
    table = SourceTable
    plots = ("impact",)
    rule = (f"PASS when there is no contact and the speed stays above {FOLLOW_MIN_SPEED_MPS:g} m/s from the "
            "ECU's first intervention until 1 s after its last; the margin is the lowest speed's distance "
            "to that bound.")

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        low = o.min_speed_intervening_mps
        ok = not o.collided and (low is None or low > FOLLOW_MIN_SPEED_MPS)
        return {"passed": ok, "verdict": "pass" if ok else "FAIL (contact or standstill)"}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        """``PASS min 1.3 m/s (0.3 over 1 m/s)`` / ``**FAIL** contact at 7.8 km/h`` / ``PASS no intervention``."""
        if row["collided"]:
            return f"{verdict_mark(row)} contact at {row['impact_kmh']:.1f} km/h"
        low = row["min_speed_intervening_mps"]
        if low is None:
            return f"{verdict_mark(row)} no intervention"
        return f"{verdict_mark(row)} min {low:.1f} m/s ({margin_text(low, FOLLOW_MIN_SPEED_MPS, 'm/s')})"


SCORING = Follow()
