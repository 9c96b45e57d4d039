"""Following a slower target (crd): the ECU brakes to zero relative speed and must not stop the car.

Pass iff no contact and the minimum speed from the first intervention until
1 s after the last stays above ``FOLLOW_MIN_SPEED_MPS``
(:func:`cosim.matrix.runner.outcome_of`).
"""

from __future__ import annotations

from typing import Any, Mapping

from ..scoring import Outcome, ScoringDefaults
from .tables import SourceTable

FOLLOW_MIN_SPEED_MPS = 1.0


class Follow(ScoringDefaults):
    name = "follow"
    table = SourceTable
    plots = ("impact",)

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        low = o.min_speed_intervening_mps
        ok = not o.collided and (low is None or low > FOLLOW_MIN_SPEED_MPS)
        return {"passed": ok, "verdict": "pass" if ok else "FAIL (contact or standstill)"}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        low = row["min_speed_intervening_mps"]
        return ("HIT " if row["collided"] else "") + ("-" if low is None else f"min {low:.1f} m/s")


SCORING = Follow()
