"""The registry of sweep subjects (:class:`cosim.sweep.subject.SweepSubject`), keyed by the ``[sweep]`` key
that names the base file."""

from __future__ import annotations

from .fleet_subject import FLEET
from .scenario_subject import SCENARIO
from .subject import SweepSubject

SUBJECTS: dict[str, SweepSubject] = {SCENARIO.kind: SCENARIO, FLEET.kind: FLEET}


def subject_of(kind: str) -> SweepSubject:
    """The subject of a sweep (or of a results table's ``subject``)."""
    return SUBJECTS[kind]
