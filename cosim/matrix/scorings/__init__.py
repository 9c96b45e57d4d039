"""The table of scorings: a catalogue's ``scoring`` key names one; one module per protocol.

Adding a protocol means one module with a :class:`~cosim.matrix.scoring.Scoring`
and one line here. An unknown name is a one-line :class:`~ecu.settings.SettingError`
naming the key (``catalogue.scoring``), with the nearest name.
"""

from __future__ import annotations

from typing import Any, Mapping

from ecu.settings import SettingError, near_miss

from ..scoring import Outcome, Scoring
from . import emergency_steering, false_positive, follow, ncap, ncap_fc, r152

SCORINGS: dict[str, Scoring] = {m.SCORING.name: m.SCORING for m in (r152, ncap, false_positive, follow, ncap_fc,
                                                                     emergency_steering)}


def scoring_named(name: str, where: str = "catalogue.scoring") -> Scoring:
    """The scoring called ``name``."""
    try:
        return SCORINGS[name]
    except KeyError:
        near = near_miss(name, SCORINGS)
        hint = f"; did you mean {near!r}?" if near else ""
        raise SettingError(where, f"expected one of {list(SCORINGS)}, got {name!r}{hint}") from None


def score_cell(scoring: str, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
    """The protocol's verdict on one cell: ``passed`` (requirement met), and what else the protocol gives."""
    if o.error is not None:
        return {"passed": False, "verdict": f"error: {o.error}"}
    return scoring_named(scoring).score(params, o)
