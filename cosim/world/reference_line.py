"""A road's reference line: straight lines, arcs and clothoids placed end to end, as OpenDRIVE's plan view.

ASAM OpenDRIVE 1.x (e.g. V1.6/V1.8, "Geometry" of the reference line: ``<planView>`` holding
``<geometry s x y hdg length>`` records with one of ``<line/>``, ``<arc curvature>``,
``<spiral curvStart curvEnd>``) describes a road's reference line as a sequence of such
segments, each with its start position ``s`` along the line, start point ``(x, y)`` and heading
``hdg``. :class:`PlanView` holds the same records (:class:`Placed`), so an OpenDRIVE import maps
one ``<geometry>`` to one :class:`Placed`; :meth:`PlanView.chained` builds them end to end.

Each segment in its own frame (start at the origin, heading 0, ``ds`` along it; curvature
``k`` positive to the left):

* line: ``x = ds``, ``y = 0``, heading 0;
* arc (constant ``k``): ``x = sin(k ds)/k``, ``y = (1 - cos(k ds))/k``, heading ``k ds``;
* spiral (clothoid, curvature linear from ``k0`` to ``k1`` over the length ``L``, ``c = (k1-k0)/L``):
  heading ``theta = k0 ds + c ds^2 / 2``, ``x = int_0^ds cos theta``, ``y = int_0^ds sin theta``
  (Fresnel integrals), evaluated with 16-point Gauss–Legendre quadrature from the nearest of
  precomputed knots spaced so that the heading turns at most 0.25 rad between knots (error below
  1e-12 m for the lengths of roads).

The frame is placed by a rotation by ``hdg`` and a translation to ``(x, y)``. Beyond its ends the
reference line continues straight along its end headings, so ``(s, t)`` is defined everywhere.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(16)
_SPIRAL_KNOT_TURN_RAD = 0.25


class Segment(Protocol):
    """One kind of reference-line geometry, in its own frame (arrays, and one float at a time: ``*_at``)."""

    length_m: float

    def local(self, ds: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x, y, heading) at ``0 <= ds <= length_m`` in the segment's frame."""

    def curvature(self, ds: np.ndarray) -> np.ndarray:
        """Curvature (1/m, positive to the left) at ``ds``."""

    def local_at(self, ds: float) -> tuple[float, float, float]:
        """:meth:`local` at one ``ds``, without numpy where the closed form allows (a moving object's hot path)."""

    def curvature_at(self, ds: float) -> float:
        """:meth:`curvature` at one ``ds``."""


def _positive_length(length_m: float, kind: str) -> None:
    if not length_m > 0.0:
        raise ValueError(f"{kind}: expected length_m > 0, got {length_m}")


@dataclass(frozen=True, slots=True)
class Line:
    """A straight line (OpenDRIVE ``<line/>``)."""

    length_m: float

    def __post_init__(self) -> None:
        _positive_length(self.length_m, "line")

    def local(self, ds):
        ds = np.asarray(ds, dtype=float)
        return ds, np.zeros_like(ds), np.zeros_like(ds)

    def curvature(self, ds):
        return np.zeros_like(np.asarray(ds, dtype=float))

    def local_at(self, ds: float) -> tuple[float, float, float]:
        return ds, 0.0, 0.0

    def curvature_at(self, ds: float) -> float:
        return 0.0


@dataclass(frozen=True, slots=True)
class Arc:
    """An arc of constant curvature (OpenDRIVE ``<arc curvature>``), 1/m, positive to the left."""

    length_m: float
    curvature_1pm: float

    def __post_init__(self) -> None:
        _positive_length(self.length_m, "arc")
        if self.curvature_1pm == 0.0:
            raise ValueError("arc: expected curvature_1pm != 0 (a straight line is a line)")

    def local(self, ds):
        ds = np.asarray(ds, dtype=float)
        k = self.curvature_1pm
        heading = k * ds
        return np.sin(heading) / k, (1.0 - np.cos(heading)) / k, heading

    def curvature(self, ds):
        return np.full_like(np.asarray(ds, dtype=float), self.curvature_1pm)

    def local_at(self, ds: float) -> tuple[float, float, float]:
        k = self.curvature_1pm
        return math.sin(k * ds) / k, (1.0 - math.cos(k * ds)) / k, k * ds

    def curvature_at(self, ds: float) -> float:
        return self.curvature_1pm


@dataclass(frozen=True, slots=True)
class Spiral:
    """A clothoid (OpenDRIVE ``<spiral curvStart curvEnd>``): curvature linear in ``ds`` from start to end."""

    length_m: float
    curvature_start_1pm: float
    curvature_end_1pm: float
    _knots: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        _positive_length(self.length_m, "spiral")
        turn = self._turn_bound()
        n = max(1, math.ceil(turn / _SPIRAL_KNOT_TURN_RAD))
        s = np.linspace(0.0, self.length_m, n + 1)
        steps = np.array([self._integrate(s[i], s[i + 1]) for i in range(n)]).reshape(-1, 2)
        xy = np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)])
        object.__setattr__(self, "_knots", np.column_stack([s, xy]))

    def _turn_bound(self) -> float:
        return max(abs(self.curvature_start_1pm), abs(self.curvature_end_1pm)) * self.length_m

    def _heading(self, ds):
        c = (self.curvature_end_1pm - self.curvature_start_1pm) / self.length_m
        return self.curvature_start_1pm * ds + 0.5 * c * ds * ds

    def _integrate(self, s0, s1):
        """``int_{s0}^{s1} (cos theta, sin theta) ds`` by Gauss–Legendre (arrays of the same shape)."""
        s0, s1 = np.asarray(s0, dtype=float), np.asarray(s1, dtype=float)
        half = 0.5 * (s1 - s0)
        tau = (s0 + half)[..., None] + half[..., None] * _GL_NODES
        theta = self._heading(tau)
        return np.stack([half * (np.cos(theta) @ _GL_WEIGHTS), half * (np.sin(theta) @ _GL_WEIGHTS)], axis=-1)

    def local(self, ds):
        ds = np.asarray(ds, dtype=float)
        i = np.clip(np.searchsorted(self._knots[:, 0], ds, side="right") - 1, 0, len(self._knots) - 1)
        base = self._knots[i]
        step = self._integrate(base[..., 0], ds)
        return base[..., 1] + step[..., 0], base[..., 2] + step[..., 1], self._heading(ds)

    def curvature(self, ds):
        ds = np.asarray(ds, dtype=float)
        return self.curvature_start_1pm + (self.curvature_end_1pm - self.curvature_start_1pm) * ds / self.length_m

    def local_at(self, ds: float) -> tuple[float, float, float]:
        x, y, h = self.local(ds)
        return float(x), float(y), float(h)

    def curvature_at(self, ds: float) -> float:
        return self.curvature_start_1pm + (self.curvature_end_1pm - self.curvature_start_1pm) * ds / self.length_m


@dataclass(frozen=True, slots=True)
class Placed:
    """A segment placed on the reference line: OpenDRIVE's ``<geometry s x y hdg length>``."""

    s_m: float
    x_m: float
    y_m: float
    heading_rad: float
    segment: Segment
    _cos_sin: tuple[float, float] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_cos_sin", (math.cos(self.heading_rad), math.sin(self.heading_rad)))

    def pose(self, ds):
        """(x, y, heading) in world coordinates at ``ds`` from this segment's start."""
        lx, ly, lh = self.segment.local(ds)
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return self.x_m + c * lx - s * ly, self.y_m + s * lx + c * ly, self.heading_rad + lh

    def pose_at(self, ds: float) -> tuple[float, float, float]:
        """:meth:`pose` at one ``ds`` (floats)."""
        lx, ly, lh = self.segment.local_at(ds)
        c, s = self._cos_sin
        return self.x_m + c * lx - s * ly, self.y_m + s * lx + c * ly, self.heading_rad + lh


@dataclass(frozen=True)
class PlanView:
    """The reference line: placed segments in order of ``s`` (OpenDRIVE ``<planView>``)."""

    placed: tuple[Placed, ...]

    def __post_init__(self) -> None:
        if not self.placed:
            raise ValueError("plan view: expected at least one segment")
        starts = [p.s_m for p in self.placed]
        if starts[0] != 0.0 or any(b <= a for a, b in zip(starts, starts[1:])):
            raise ValueError(f"plan view: expected segment starts increasing from 0, got {starts}")
        object.__setattr__(self, "_starts", tuple(starts))

    @classmethod
    def chained(cls, segments: tuple[Segment, ...] | list[Segment], x_m: float = 0.0, y_m: float = 0.0,
                heading_rad: float = 0.0) -> PlanView:
        """Segments end to end from the start pose (each starts where the previous one ends)."""
        placed, s = [], 0.0
        for seg in segments:
            placed.append(Placed(s, x_m, y_m, heading_rad, seg))
            x, y, h = placed[-1].pose(seg.length_m)
            x_m, y_m, heading_rad, s = float(x), float(y), float(h), s + seg.length_m
        return cls(tuple(placed))

    @property
    def length_m(self) -> float:
        last = self.placed[-1]
        return last.s_m + last.segment.length_m

    def _index(self, s: np.ndarray) -> np.ndarray:
        starts = np.array([p.s_m for p in self.placed])
        return np.clip(np.searchsorted(starts, s, side="right") - 1, 0, len(self.placed) - 1)

    def pose(self, s) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x, y, heading) of the reference line at ``s`` (array or float); straight on beyond the ends."""
        s = np.asarray(s, dtype=float)
        x, y, h = np.empty_like(s), np.empty_like(s), np.empty_like(s)
        idx = self._index(s)
        for i, p in enumerate(self.placed):
            m = idx == i
            if not m.any():
                continue
            ds = np.clip(s[m] - p.s_m, 0.0, p.segment.length_m)
            xi, yi, hi = p.pose(ds)
            beyond = s[m] - p.s_m - ds  # nonzero only before the start or after the end of the line
            x[m], y[m], h[m] = xi + beyond * np.cos(hi), yi + beyond * np.sin(hi), hi
        return x, y, h

    def pose_at(self, s: float) -> tuple[float, float, float]:
        """:meth:`pose` at one station ``s`` (floats; the same equations, no arrays)."""
        return self.pose_curvature_at(s)[:3]

    def pose_curvature_at(self, s: float) -> tuple[float, float, float, float]:
        """(x, y, heading, curvature) at one station ``s``: :meth:`pose_at` and :meth:`curvature_at` in one look-up."""
        p = self.placed[max(0, bisect.bisect_right(self._starts, s) - 1)]
        ds = min(max(s - p.s_m, 0.0), p.segment.length_m)
        x, y, h = p.pose_at(ds)
        beyond = s - p.s_m - ds  # nonzero only before the start or after the end of the line
        if beyond == 0.0:
            return x, y, h, p.segment.curvature_at(ds)
        return x + beyond * math.cos(h), y + beyond * math.sin(h), h, 0.0

    def curvature_at(self, s: float) -> float:
        """:meth:`curvature` at one station ``s``; 0 beyond the ends."""
        if not 0.0 <= s <= self.length_m:
            return 0.0
        p = self.placed[max(0, bisect.bisect_right(self._starts, s) - 1)]
        return p.segment.curvature_at(s - p.s_m)

    def curvature(self, s) -> np.ndarray:
        """Curvature (1/m) at ``s``; 0 beyond the ends."""
        s = np.asarray(s, dtype=float)
        k = np.zeros_like(s)
        idx = self._index(s)
        for i, p in enumerate(self.placed):
            m = (idx == i) & (s >= 0.0) & (s <= self.length_m)
            if m.any():
                k[m] = p.segment.curvature(s[m] - p.s_m)
        return k
