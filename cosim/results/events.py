"""A run's events, rate-limited and summarised; which of them are faults.

A dead peer can make every frame of a long run fail (finding 8 of issue 15:
114,074 ``bus_error`` events, a 20 MB ``events.json``, as many log lines).
:class:`EventLog` keeps a run's events readable:

* the first :data:`KEEP_FIRST` events of each kind are kept in full;
* after that at most one of that kind per :data:`KEEP_EVERY_S` of simulated
  time is kept, and the others are only counted;
* :meth:`EventLog.summaries` gives one ``events_suppressed`` event per kind
  that lost any: how many in all, from which time to which, how many kept.

``EventLog.add`` returns whether the event was kept, so a caller logs exactly
the events it keeps (the log is rate-limited the same way).

Faults: :data:`FAULT_EVENTS` are the kinds that make ``crd run``/``crd paper``
exit with :data:`EXIT_FAULT_EVENT` (4) unless ``[checks] expect_events``
lists them (:func:`unexpected_faults`).
"""

from __future__ import annotations

from collections import Counter
from typing import Iterable, Sequence

from .run_record import RunEvent, RunRecord

KEEP_FIRST = 10
KEEP_EVERY_S = 10.0
EXIT_FAULT_EVENT = 4
SUPPRESSED = "events_suppressed"


class EventLog(list):
    """A list of :class:`RunEvent` that keeps the first few of each kind, then one per ``every_s``.

    ``append`` (the list API) applies the same limit as :meth:`add`.
    """

    def __init__(self, events: Iterable[RunEvent] = (), keep_first: int = KEEP_FIRST,
                 every_s: float = KEEP_EVERY_S) -> None:
        super().__init__()
        self._keep_first, self._every_s = keep_first, every_s
        self._seen: Counter[str] = Counter()
        self._kept: Counter[str] = Counter()
        self._first_t: dict[str, float] = {}
        self._last_t: dict[str, float] = {}
        self._last_kept_t: dict[str, float] = {}
        for event in events:
            self.add(event)

    def add(self, event: RunEvent) -> bool:
        """Count ``event``; keep it if within the limits. Returns True if kept (then log it)."""
        kind, t_s = event.kind, event.t_s
        n = self._seen[kind] = self._seen[kind] + 1
        self._first_t.setdefault(kind, t_s)
        self._last_t[kind] = t_s
        if n > self._keep_first and t_s - self._last_kept_t[kind] < self._every_s:
            return False
        self._kept[kind] += 1
        self._last_kept_t[kind] = t_s
        super().append(event)
        return True

    append = add  # type: ignore[assignment]

    def __reduce__(self):
        """Pickle (e.g. a record sent back by a Dask worker) with the counts, bypassing the limit."""
        return _rebuild, (list(self), self.__dict__.copy())

    def extend(self, events: Iterable[RunEvent]) -> None:  # type: ignore[override]
        for event in events:
            self.add(event)

    def absorb_counts(self, other: "EventLog") -> None:
        """Add the events ``other`` only counted (its kept ones are added as events)."""
        for kind, n in other._seen.items():
            dropped = n - other._kept[kind]
            if dropped:
                self._seen[kind] += dropped
                self._first_t[kind] = min(self._first_t.get(kind, other._first_t[kind]), other._first_t[kind])
                self._last_t[kind] = max(self._last_t.get(kind, other._last_t[kind]), other._last_t[kind])

    @property
    def counts(self) -> dict[str, int]:
        """Events seen of each kind, kept or not."""
        return dict(self._seen)

    def summaries(self) -> list[RunEvent]:
        """One ``events_suppressed`` event per kind of which some were only counted."""
        out = []
        for kind, n in self._seen.items():
            if n > self._kept[kind]:
                out.append(RunEvent(self._last_t[kind], SUPPRESSED,
                                    f"{kind}: {n} in all from t = {self._first_t[kind]:.3f} s to "
                                    f"t = {self._last_t[kind]:.3f} s; {self._kept[kind]} recorded (the first "
                                    f"{self._keep_first}, then one per {self._every_s:g} s), {n - self._kept[kind]}"
                                    " counted only"))
        return out


def _rebuild(events: list[RunEvent], state: dict) -> EventLog:
    log = EventLog()
    log.__dict__.update(state)
    list.extend(log, events)
    return log


def merge_events(*sources: Sequence[RunEvent]) -> EventLog:
    """The events of every source in time order, limited per kind, then the summaries.

    A source that is an :class:`EventLog` contributes what it saw, not only what it kept.
    """
    merged = EventLog()
    for event in sorted((e for s in sources for e in s), key=lambda e: e.t_s):
        merged.add(event)
    for source in sources:
        if isinstance(source, EventLog):
            merged.absorb_counts(source)
    for event in merged.summaries():
        list.append(merged, event)
    merged.sort(key=lambda e: e.t_s)
    return merged


def event_counts(record: RunRecord) -> dict[str, int]:
    """Events of each kind in the run, including those only counted."""
    if isinstance(record.events, EventLog):
        return record.events.counts
    return dict(Counter(e.kind for e in record.events))


def __getattr__(name: str) -> tuple[str, ...]:
    """``FAULT_EVENTS``: the kinds a run with one of them (not expected by ``[checks] expect_events``)
    exits with EXIT_FAULT_EVENT for; the scenario's ``EXPECTABLE_EVENTS``, read on first use: a plot
    worker imports this module to unpickle a record's :class:`EventLog`, and the scenario config
    would bring can_dbc with it (about 14 MB)."""
    if name == "FAULT_EVENTS":
        from ..scenarios.config import EXPECTABLE_EVENTS

        return EXPECTABLE_EVENTS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def unexpected_faults(records: Iterable[RunRecord], expected: Iterable[str] = ()) -> list[str]:
    """One line per run and fault kind (:data:`FAULT_EVENTS`) that ``expected`` does not list: its first event."""
    allowed, out, faults = set(expected), [], __getattr__("FAULT_EVENTS")
    for record in records:
        seen: set[str] = set()
        for e in record.events:
            if e.kind in faults and e.kind not in allowed and e.kind not in seen:
                seen.add(e.kind)
                out.append(f"{record.strategy}: t={e.t_s:.3f} s {e.kind}: {e.detail}")
    return out


def fault_exit(records: Iterable[RunRecord], expected: Iterable[str] = ()) -> int:
    """:data:`EXIT_FAULT_EVENT` if any run had a fault event ``expected`` does not list, else 0."""
    return EXIT_FAULT_EVENT if unexpected_faults(records, expected) else 0
