"""``[scoring]`` tables of a catalogue, declared once per key (:func:`ecu.settings.setting`)."""

from __future__ import annotations

from dataclasses import dataclass

from ecu.settings import setting


@dataclass(frozen=True)
class SourceTable:
    """``[scoring]`` of a protocol whose rule takes no parameters: only the source it cites."""

    source: str = setting("", doc="the key(s) of [sources] the scoring rule cites, joined by +")
