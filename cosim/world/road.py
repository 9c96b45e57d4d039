"""A road: a reference line with lanes of given widths to its left and right, as OpenDRIVE's lane model.

ASAM OpenDRIVE 1.x ("Lanes": ``<lanes>`` with ``<laneSection s>``, each holding ``<left>``,
``<center>`` and ``<right>`` lanes; a lane's ``<width sOffset a b c d>`` records) is followed:

* the centre lane (id 0) lies on the reference line and has no width (OpenDRIVE's
  ``<laneOffset>``, which shifts it, is not supported yet: it is zero here);
* left lanes have ids 1, 2, ... outward (``t > 0``), right lanes -1, -2, ... (``t < 0``);
* a lane's width at ``ds`` from its section's start is the cubic of its last width record with
  ``sOffset <= ds``: ``w = a + b u + c u^2 + d u^3``, ``u = ds - sOffset``;
* a lane section applies from its ``s`` to the next section's.

Road coordinates ``(s, t)``: ``s`` along the reference line, ``t`` across it, positive to the
left. The world point of ``(s, t)`` is ``P(s) + t N(s)`` with ``P`` the reference line and
``N = (-sin h, cos h)`` its left normal (OpenDRIVE's reference-line coordinate system);
:meth:`Road.to_st` inverts it by projecting onto the reference line (Newton's method on
``(P(s) - p) . T(s) = 0``, ``T`` the unit tangent, from the nearest point of a dense sampling).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .reference_line import PlanView

#: sampling step (m) of the reference line for the start of the projection (then refined by Newton)
_SAMPLE_STEP_M = 0.5
_NEWTON_STEPS = 8


@dataclass(frozen=True, slots=True)
class LaneWidth:
    """One OpenDRIVE ``<width>`` record: ``w(ds) = a + b u + c u^2 + d u^3``, ``u = ds - s_offset_m``."""

    s_offset_m: float
    a: float
    b: float = 0.0
    c: float = 0.0
    d: float = 0.0


@dataclass(frozen=True, slots=True)
class Lane:
    """A lane: its id (left > 0, right < 0), OpenDRIVE lane type and width records (by ``s_offset_m``)."""

    id: int
    widths: tuple[LaneWidth, ...]
    type: str = "driving"

    def __post_init__(self) -> None:
        if self.id == 0 or not self.widths or self.widths[0].s_offset_m != 0.0:
            raise ValueError(f"lane {self.id}: expected a nonzero id and width records starting at s_offset_m 0")

    def width_m(self, ds) -> np.ndarray:
        """Width (m) at ``ds`` from the section's start (array or float)."""
        ds = np.asarray(ds, dtype=float)
        offsets = np.array([w.s_offset_m for w in self.widths])
        i = np.clip(np.searchsorted(offsets, ds, side="right") - 1, 0, len(self.widths) - 1)
        coef = np.array([(w.a, w.b, w.c, w.d) for w in self.widths])[i]
        u = ds - offsets[i]
        return coef[..., 0] + u * (coef[..., 1] + u * (coef[..., 2] + u * coef[..., 3]))


@dataclass(frozen=True, slots=True)
class LaneSection:
    """Lanes from ``s_m`` on: ``left`` ordered 1, 2, ... and ``right`` ordered -1, -2, ... (outward)."""

    s_m: float
    left: tuple[Lane, ...] = ()
    right: tuple[Lane, ...] = ()

    def __post_init__(self) -> None:
        ids_l, ids_r = [ln.id for ln in self.left], [ln.id for ln in self.right]
        if ids_l != list(range(1, len(ids_l) + 1)) or ids_r != list(range(-1, -len(ids_r) - 1, -1)):
            raise ValueError(f"lane section at s={self.s_m}: expected left ids 1, 2, ... and right ids -1, -2, ...,"
                             f" got {ids_l} and {ids_r}")

    @classmethod
    def uniform(cls, s_m: float = 0.0, left_m: tuple[float, ...] = (), right_m: tuple[float, ...] = ()) -> LaneSection:
        """Driving lanes of constant widths, listed outward from the reference line."""
        return cls(s_m, tuple(Lane(i + 1, (LaneWidth(0.0, w),)) for i, w in enumerate(left_m)),
                   tuple(Lane(-(i + 1), (LaneWidth(0.0, w),)) for i, w in enumerate(right_m)))

    def lanes(self) -> tuple[Lane, ...]:
        return self.left + self.right

    def borders_m(self, ds) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        """Lane id -> (inner, outer) border ``t`` (m) at ``ds`` from the section's start."""
        out: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        for side, sign in ((self.left, 1.0), (self.right, -1.0)):
            inner = np.zeros_like(np.asarray(ds, dtype=float))
            for lane in side:
                outer = inner + sign * lane.width_m(ds)
                out[lane.id] = (inner, outer)
                inner = outer
        return out


@dataclass(frozen=True)
class Road:
    """A reference line (:class:`~cosim.world.reference_line.PlanView`) and its lane sections."""

    plan: PlanView
    sections: tuple[LaneSection, ...]
    _samples: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        starts = [sec.s_m for sec in self.sections]
        if not starts or starts[0] != 0.0 or any(b <= a for a, b in zip(starts, starts[1:])):
            raise ValueError(f"road: expected lane sections starting at s=0 in increasing order, got {starts}")
        s = np.linspace(0.0, self.length_m, max(2, math.ceil(self.length_m / _SAMPLE_STEP_M) + 1))
        x, y, _ = self.plan.pose(s)
        object.__setattr__(self, "_samples", np.column_stack([s, x, y]))

    @property
    def length_m(self) -> float:
        return self.plan.length_m

    # -- coordinates -----------------------------------------------------------
    def pose(self, s, t=0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World (x, y) of road coordinates (s, t) and the reference line's heading there (rad)."""
        x, y, h = self.plan.pose(s)
        t = np.asarray(t, dtype=float)
        return x - t * np.sin(h), y + t * np.cos(h), h

    def pose_at(self, s_m: float, t_m: float = 0.0) -> tuple[float, float, float, float]:
        """:meth:`pose` at one point (floats, no arrays), and the reference line's curvature there (1/m)."""
        x, y, h, k = self.plan.pose_curvature_at(s_m)
        return x - t_m * math.sin(h), y + t_m * math.cos(h), h, k

    def to_st(self, x_m: float, y_m: float) -> tuple[float, float]:
        """Road coordinates (s, t) of the world point (x, y): its projection on the reference line."""
        d2 = (self._samples[:, 1] - x_m) ** 2 + (self._samples[:, 2] - y_m) ** 2
        s = float(self._samples[int(np.argmin(d2)), 0])
        for _ in range(_NEWTON_STEPS):
            px, py, h = (float(v) for v in self.plan.pose(s))
            k = float(self.plan.curvature(s))
            rx, ry = px - x_m, py - y_m
            f = rx * math.cos(h) + ry * math.sin(h)  # (P - p) . T
            slope = 1.0 + k * (-rx * math.sin(h) + ry * math.cos(h))  # d/ds: 1 + k (P - p) . N
            step = f / slope if slope > 0.1 else f
            s -= step
            if abs(step) < 1e-12:
                break
        px, py, h = (float(v) for v in self.plan.pose(s))
        return s, (x_m - px) * -math.sin(h) + (y_m - py) * math.cos(h)

    # -- lanes -------------------------------------------------------------------
    def section_at(self, s: float) -> LaneSection:
        starts = [sec.s_m for sec in self.sections]
        return self.sections[max(0, int(np.searchsorted(starts, s, side="right")) - 1)]

    def lane_at(self, s: float, t: float) -> int | None:
        """The id of the lane holding (s, t), or None off the road (outside 0 <= s <= length or the edges).

        A point on the border between two lanes belongs to the inner one (nearer the reference line); a point
        on the reference line to lane -1 (right-hand traffic's driving side), or to lane 1 without right lanes.
        """
        if not 0.0 <= s <= self.length_m:
            return None
        sec = self.section_at(s)
        borders = sec.borders_m(s - sec.s_m)
        if t == 0.0:
            side = sec.right if sec.right else sec.left
            return side[0].id if side and borders[side[0].id][0] != borders[side[0].id][1] else None
        for lane_id, (inner, outer) in borders.items():
            if (inner < t <= outer) if lane_id > 0 else (outer <= t < inner):
                return lane_id
        return None

    def lane_of_point(self, x_m: float, y_m: float) -> int | None:
        """The lane holding the world point (x, y), or None off the road."""
        return self.lane_at(*self.to_st(x_m, y_m))

    def is_on_road(self, x_m: float, y_m: float) -> bool:
        """Whether (x, y) lies on the road (between its edges, within its length)."""
        return self.lane_of_point(x_m, y_m) is not None

    def _border_t(self, s: np.ndarray, lane_id: int, which: int) -> np.ndarray:
        """``t`` of a lane's inner (0) or outer (1) border at each ``s``; NaN where the lane does not exist."""
        t = np.full_like(s, np.nan)
        for k, sec in enumerate(self.sections):
            end = self.sections[k + 1].s_m if k + 1 < len(self.sections) else math.inf
            m = (s >= sec.s_m) & (s <= end)
            borders = sec.borders_m(s[m] - sec.s_m)
            if lane_id in borders:
                t[m] = borders[lane_id][which]
        return t

    def _stations(self, step_m: float) -> np.ndarray:
        return np.linspace(0.0, self.length_m, max(2, math.ceil(self.length_m / step_m) + 1))

    def lane_centre_line(self, lane_id: int, step_m: float = 1.0) -> np.ndarray:
        """A lane's centre line as a polyline, shape (k, 2) (NaN rows where the lane does not exist)."""
        s = self._stations(step_m)
        t = 0.5 * (self._border_t(s, lane_id, 0) + self._border_t(s, lane_id, 1))
        x, y, _ = self.pose(s, t)
        return np.column_stack([x, y])

    def lane_border_line(self, lane_id: int, step_m: float = 1.0) -> np.ndarray:
        """A lane's outer border as a polyline, shape (k, 2) (NaN where the lane does not exist)."""
        s = self._stations(step_m)
        x, y, _ = self.pose(s, self._border_t(s, lane_id, 1))
        return np.column_stack([x, y])

    def edges(self, step_m: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """The left and right road edges (outer borders of the outermost lanes) as polylines, shape (k, 2)."""
        s = self._stations(step_m)
        t_left, t_right = np.zeros_like(s), np.zeros_like(s)
        for k, sec in enumerate(self.sections):
            end = self.sections[k + 1].s_m if k + 1 < len(self.sections) else math.inf
            m = (s >= sec.s_m) & (s <= end)
            borders = sec.borders_m(s[m] - sec.s_m)
            if sec.left:
                t_left[m] = borders[sec.left[-1].id][1]
            if sec.right:
                t_right[m] = borders[sec.right[-1].id][1]
        (xl, yl, _), (xr, yr, _) = self.pose(s, t_left), self.pose(s, t_right)
        return np.column_stack([xl, yl]), np.column_stack([xr, yr])

    def lane_ids(self) -> list[int]:
        """Every lane id of the road, left to right."""
        ids = {lane.id for sec in self.sections for lane in sec.lanes()}
        return sorted(ids, reverse=True)
