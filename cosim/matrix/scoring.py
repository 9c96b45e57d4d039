"""The seam between a catalogue's cells and the protocol that scores them.

:class:`Outcome` is what one run of one cell at one radar phase produced;
:class:`Scoring` is the typed Protocol every protocol's scoring implements, one
module each under :mod:`cosim.matrix.scorings`, registered in one table
(:data:`cosim.matrix.scorings.SCORINGS`) that a catalogue's ``scoring`` key
names. :class:`ScoringDefaults` holds what most scorings share.

With several radar phases a cell is scored on its worst phase
(:func:`worst`): the highest impact speed, the most interventions, the lowest speed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar, Iterable, Mapping, Protocol, Sequence

if TYPE_CHECKING:
    from .planar_outcome import PlanarOutcome

RESTRICTING_MODES = ("TIGHTENING", "CONTINGENCY")
KMH = 3.6


@dataclass(frozen=True)
class Outcome:
    """What one run of one cell at one phase produced (plain data, crosses process boundaries)."""

    collided: bool
    impact_kmh: float
    interventions: int
    min_speed_intervening_mps: float | None
    min_gap_m: float | None
    end_reason: str | None
    sim_time_s: float
    wall_time_s: float
    error: str | None = None
    #: a planar cell's additions (:class:`cosim.matrix.planar_outcome.PlanarOutcome`); None in the 1-D world
    planar: PlanarOutcome | None = None


def interventions(modes: Sequence[str]) -> int:
    """Entries into a restricting mode (or a FAULT after start-up) in the per-cycle ECU modes."""
    count, started, prev = 0, False, None
    for mode in modes:
        if mode == "STANDBY":
            started = True
        entering = mode != prev
        if entering and (mode in RESTRICTING_MODES or (started and mode == "FAULT")):
            count += 1
        prev = mode
    return count


def worst(outcomes: Iterable[Outcome]) -> Outcome:
    """The worst phase: an error first, then contact at the highest speed, most interventions, lowest speed."""
    def badness(o: Outcome) -> tuple:
        low = o.min_speed_intervening_mps
        return (o.error is not None, o.collided, o.impact_kmh, o.interventions, -(low if low is not None else 1e9))
    return max(outcomes, key=badness)




class Scoring(Protocol):
    """How one protocol scores a catalogue's cells, and how the report shows them."""

    name: ClassVar[str]  #: the catalogue's ``scoring`` value
    table: ClassVar[type]  #: the declared ``[scoring]`` table of a catalogue (ecu.settings)
    plots: ClassVar[tuple[str, ...]]  #: report figures: "impact" (against test speed), "bands" (colour grid)
    limit_header: ClassVar[str]  #: an extra column of the report's cell table ("": none)
    rule: ClassVar[str]  #: how to read a cell: what PASS/FAIL (or the band) means, for the report's legend
    required_keys: ClassVar[tuple[str, ...]]  #: cell keys every series of such a catalogue must give

    def score(self, params: Mapping[str, Any], o: Outcome) -> dict[str, Any]:
        """The verdict on one cell's worst phase: ``passed``, ``verdict`` (and what else the protocol gives)."""

    def row_fields(self, params: Mapping[str, Any]) -> dict[str, Any]:
        """Cell values the result row carries for this protocol (before the verdict)."""

    def cell_text(self, row: Mapping[str, Any]) -> str:
        """A row's cell in the report's table, verdict first, then the figure and its margin to the
        requirement (an error is shown by the caller)."""

    def limit_text(self, row: Mapping[str, Any]) -> str:
        """The row's entry in the ``limit_header`` column."""

    def summary(self, rows: Sequence[Mapping[str, Any]], table: Any) -> str:
        """What the summary line of one strategy adds (its rows of one catalogue)."""


class ScoringDefaults:
    """No extra row fields, no limit column, nothing to add to the summary."""

    limit_header: ClassVar[str] = ""
    required_keys: ClassVar[tuple[str, ...]] = ()

    def row_fields(self, params: Mapping[str, Any]) -> dict[str, Any]:
        return {}

    def limit_text(self, row: Mapping[str, Any]) -> str:
        return ""

    def summary(self, rows: Sequence[Mapping[str, Any]], table: Any) -> str:
        return ""


def verdict_mark(row: Mapping[str, Any]) -> str:
    """``PASS`` or ``**FAIL**`` (bold, so that a failed cell stands out in a table)."""
    return "PASS" if row["passed"] else "**FAIL**"


def no_contact_text(row: Mapping[str, Any]) -> str:
    """``no contact (min gap 2.6 m)``: the gap is the margin of a cell without contact."""
    gap = row.get("min_gap_m")
    return "no contact" + ("" if gap is None else f" (min gap {gap:.1f} m)")


def margin_text(value: float, limit: float, unit: str) -> str:
    """``27.1 under 35`` / ``7.5 over 0``: how far ``value`` is from ``limit``, and on which side."""
    side = "under" if value <= limit else "over"
    return f"{abs(limit - value):.1f} {side} {limit:g} {unit}"
