"""Target classes: the test targets of the protocols, with their dimensions and sources.

The Euro NCAP targets are defined by ISO 19206 (Euro NCAP Crash Avoidance – Frontal Collisions
v1.1, Oct 2025, "Definitions" and §1.4): EPTa and EPTc (adult and child pedestrian, ISO
19206-2:2018), EBTa (bicyclist and bicycle, ISO 19206-4:2020), GVT (global vehicle target, ISO
19206-3:2021) and EMT (motorcyclist, ISO 19206-5). The protocol gives the boxes only in figures;
the lengths and widths below are the bounding boxes of the OpenSCENARIO catalogue of
``vectorgrp/OSC-NCAP-scenarios`` (@ee7aa11, third party), as collected in
``planar-protocol-facts.md`` §1.1. The box's length is along the target's heading (its direction
of travel), its width across.

``size_class`` is what a radar reports of the object (:mod:`cosim.world.radar2d`); the choices
are :data:`SIZE_CLASSES`.
"""

from __future__ import annotations

from dataclasses import dataclass

#: radar size classes (the order is their code in a track)
SIZE_CLASSES = ("unknown", "pedestrian", "bicycle", "motorcycle", "car", "truck")

_VECTOR = "vectorgrp/OSC-NCAP-scenarios @ee7aa11 catalogue box (planar-protocol-facts.md §1.1)"


@dataclass(frozen=True, slots=True)
class TargetClass:
    """A kind of target: its box (m), its radar size class and where the numbers come from."""

    name: str
    length_m: float
    width_m: float
    height_m: float | None  # None: not given by the source
    size_class: str
    source: str

    def __post_init__(self) -> None:
        if self.size_class not in SIZE_CLASSES:
            raise ValueError(f"target class {self.name}: size_class must be one of {SIZE_CLASSES},"
                             f" got {self.size_class!r}")


#: name -> target class
TARGET_CLASSES: dict[str, TargetClass] = {t.name: t for t in (
    TargetClass("EPTa", 0.60, 0.50, 1.80, "pedestrian", f"ISO 19206-2:2018 adult; {_VECTOR}"),
    TargetClass("EPTc", 0.711, 0.298, 1.154, "pedestrian", f"ISO 19206-2:2018 child; {_VECTOR}"),
    TargetClass("EBTa", 1.89, 0.50, 1.20, "bicycle", f"ISO 19206-4:2020 bicyclist; {_VECTOR}"),
    TargetClass("EMT", 2.08, 0.79, None, "motorcycle", f"ISO 19206-5 motorcyclist; {_VECTOR}"),
    TargetClass("GVT", 4.023, 1.712, 1.427, "car", f"ISO 19206-3:2021 global vehicle target; {_VECTOR}"),
)}


def target_class(name: str) -> TargetClass:
    """The target class called ``name``; a ``KeyError`` naming the known ones otherwise."""
    try:
        return TARGET_CLASSES[name]
    except KeyError:
        raise KeyError(f"unknown target class {name!r}; known: {sorted(TARGET_CLASSES)}") from None
