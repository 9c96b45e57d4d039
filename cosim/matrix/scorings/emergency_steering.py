"""Emergency steering (crd): avoid the obstacle without touching anything else and without leaving the road.

No protocol publishes a pass mark for these cells (Euro NCAP FC v1.1 §5.3.2 leaves the AES test
method to the manufacturer; planar-protocol-facts.md §3.2), so the rule is UN R79 Rev.4's for an
emergency steering function, made measurable: it acts only on a detected collision risk and must
not lead the vehicle off the road nor into another road user. A cell PASSes when there was no
contact and no corner of the ego's box got more than :data:`DEPARTURE_TOL_M` beyond the road's
edge (:mod:`cosim.matrix.planar_outcome`). Its figures: the object touched (the primary target, or
another: a secondary collision), the relative impact speed, the road departure.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from ..scoring import Outcome, ScoringDefaults, no_contact_text, verdict_mark
from .tables import SourceTable

#: a box corner this far (m) beyond the road's edge is a departure (0: any part of the car off the road)
DEPARTURE_TOL_M = 0.0


class EmergencySteering(ScoringDefaults):
    name = "emergency_steering"
    table = SourceTable
    plots = ("impact",)
    rule = ("PASS when there was no contact with anything and the ego's box never got beyond the road's edge "
            "(UN R79 ESF: not off the road, not into another road user); otherwise the object touched and the "
            "relative impact speed, or how far the car left the road.")

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        departure = o.planar.road_departure_m if o.planar is not None else 0.0
        off_road = departure > DEPARTURE_TOL_M
        ok = not o.collided and not off_road
        why = "contact" if o.collided else "left the road" if off_road else ""
        return {"passed": ok, "verdict": "pass" if ok else f"FAIL ({why})"}

    def cell_text(self, row: Mapping[str, Any]) -> str:
        """``PASS no contact (min gap 0.8 m)`` / ``**FAIL** 31.2 km/h on stopped car`` / ``**FAIL** off the road by
        0.6 m``."""
        parts = []
        if row["collided"]:
            parts.append(f"{row['impact_kmh']:.1f} km/h on {row.get('hit_object') or 'an object'}")
        else:
            parts.append(no_contact_text(row))
        departure = row.get("road_departure_m") or 0.0
        if departure > DEPARTURE_TOL_M:
            parts.append(f"off the road by {departure:.2f} m")
        return f"{verdict_mark(row)} " + ", ".join(parts)

    def summary(self, rows: Sequence[Mapping[str, Any]], table: Any) -> str:
        hit = sum(r["collided"] for r in rows)
        off = sum((r.get("road_departure_m") or 0.0) > DEPARTURE_TOL_M for r in rows)
        return f"  contacts {hit}, road departures {off}"


SCORING = EmergencySteering()
