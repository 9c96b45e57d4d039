"""crd's trajectory speeds (knots over path length) as a chain of OpenSCENARIO ``<SpeedAction>`` segments, and back.

crd's knots ``(s_i, v_i)`` give the speed over the path length, with a constant acceleration between
consecutive knots and the speed held after the last one
(:meth:`cosim.world.trajectory.SpeedProfile.over_distance`). In the file:

* the first knot ``(0, v_0)`` is the object's Init speed;
* each pair of consecutive knots whose speeds differ is one :class:`Segment`: a linear ``<SpeedAction>``
  to ``v_i`` over the distance ``s_i - s_(i-1)``, started when the object has travelled ``s_(i-1)``
  along its path (``<TraveledDistanceCondition>``; at ``s = 0``, with the trajectory itself);
* between knots of the same speed nothing is written: the speed stays.

Read back (:func:`knots`), a segment's start is a knot (the condition's number, exact), its end the
next knot (``start + distance``, or the next segment's start when the two join within
:data:`JOIN_TOL_M`), and a gap between one segment's end and the next one's start a stretch at
constant speed. The export writes knots only when they read back as the same numbers
(:func:`segments` and :func:`knots` are each other's inverse there).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

#: how far a segment may start from the previous one's end and still join it (m)
JOIN_TOL_M = 1e-6


class OverlapError(ValueError):
    """A segment that starts before the previous one ends; ``index`` is its place in the list."""

    def __init__(self, message: str, index: int) -> None:
        super().__init__(message)
        self.index = index


@dataclass(frozen=True)
class Segment:
    """A linear speed change to ``target_mps`` over ``length_m`` of path, from path length ``start_m``."""

    start_m: float
    length_m: float
    target_mps: float


def segments(knots: Sequence[Sequence[float]]) -> list[Segment]:
    """The speed changes between consecutive knots (those of the same speed give none)."""
    return [Segment(s0, s1 - s0, v1) for (s0, v0), (s1, v1) in zip(knots, knots[1:]) if v1 != v0]


def knots(v0_mps: float, segs: Sequence[Segment]) -> list[list[float]]:
    """The knots of an Init speed and the segments in path order (:class:`OverlapError` if they overlap)."""
    out = [[0.0, v0_mps]]
    for i, seg in enumerate(segs):
        s, v = out[-1]
        if seg.start_m < s - JOIN_TOL_M:
            raise OverlapError(f"a speed change from {seg.start_m:g} m starts before the previous one ends at "
                               f"{s:g} m", i)
        if seg.start_m > s + JOIN_TOL_M:
            out.append([seg.start_m, v])  # the speed stays until this change starts
        elif len(out) > 1:
            out[-1][0] = seg.start_m  # joined: the start's number is the knot as written
        out.append([seg.start_m + seg.length_m, seg.target_mps])
    return out
