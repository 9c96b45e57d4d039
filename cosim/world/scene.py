"""The scene: every object around the ego, in the plane; contact, the radar's choice of object, end conditions.

One world for every scenario. Objects are oriented boxes (:mod:`cosim.world.scene_objects`); the
ego is its plant's box (:mod:`cosim.world.ego`). What the ego sees of an object is worked out in the
**ego frame**: origin at its front bumper's centre, ``u`` along its heading, ``n`` to its left. For
an object whose box reaches ``f`` ahead of its reference point and ``b`` behind it, width ``w``, at
relative heading ``Δ`` (``cΔ = cos Δ``, ``sΔ = sin Δ``) and reference point ``(a_x, a_y)`` in that
frame::

    gap  = a_x + min(f cΔ, -b cΔ) - (w/2)|sΔ|       the nearest point along the heading
    far  = a_x + max(f cΔ, -b cΔ) + (w/2)|sΔ|       the farthest
    y_c  = a_y + ((f - b)/2) sΔ                     the box's centre across
    h_y  = ((f + b)/2)|sΔ| + (w/2)|cΔ|              its half extent across

On the 1-D path (both headings 0, so ``cΔ = 1`` and ``sΔ = 0`` exactly; reference point the rear,
``b = 0``) these are the 1-D world's ``rear - bumper``, ``rear + length - bumper``, ``y`` and
``width/2`` to the last bit: every term that vanishes is a product with an exact 0.

* **gap** (``gap_m``, the triggers): the nearest object ahead whose body overlaps the ego's across
  (``|y_c| < W/2 + h_y``) and has not been passed (``far > -L``), ``W``, ``L`` the ego's width and
  length.
* **contact**: the separating-axis test of the two boxes (:mod:`cosim.world.geometry`): on the ego's
  axes as intervals, ``gap <= 0``, ``far > -L``, ``|y_c| < W/2 + h_y`` (touching along the heading
  is contact, beside it is not, as in 1-D), and, for an object not aligned with the ego, on the
  object's own two axes. The contact point and normal come from the two boxes at this step and the
  step before (:func:`~cosim.world.geometry.swept_contact`).
* **radar** (``ObjectTrack``, one object): among the objects ahead (``0 < gap <= max_range_m``)
  whose nearest point across (``max(0, |y_c| - h_y)``) is within ``±field_of_view_deg/2`` of the
  bore sight at that range, the nearest one in the lane corridor (``|y_c| - h_y < 1.75 m``), else
  the nearest one. Range: ``gap``; range rate: the object's velocity relative to the front bumper,
  along the ego's heading (a standing object closes at the ego's speed, also in a turn); lateral:
  ``y_c``. The "closest in-path object" of a production radar's object selection: an in-lane target
  is never hidden by one beside the lane, and one beside the lane is reported when nothing is in
  it, so that the ECU's own relevance check (``ObjectLateral``, ``ecu/core/relevance.py``) decides.
"""

from __future__ import annotations

import math
from typing import NamedTuple, Sequence

from ..scenarios.config import EndConfig, RadarConfig
from .ego import Ego, EgoBody
from .scene_motion import BodyState
from .scene_objects import SceneObject

#: half of a 3.5 m lane: the radar's in-lane corridor for its object selection ([M], class value).
LANE_HALF_WIDTH_M = 1.75
_ACCEL_BOUND_MPS2 = 50.0  # no body changes speed faster than this within a cycle (contact look-ahead)


class Truth(NamedTuple):
    """What the radar sees of the chosen object: gap (m), range rate (m/s), centre offset (m)."""

    gap_m: float
    range_rate_mps: float
    lateral_m: float


class Relative(NamedTuple):
    """One object seen from the ego (module docstring): gap, far end, centre across and half extent across (m),
    its velocity along the ego's heading (m/s); ``aligned``: its axes are the ego's."""

    obj: SceneObject
    state: BodyState
    gap_m: float
    far_m: float
    y_c_m: float
    half_y_m: float
    speed_along_mps: float
    aligned: bool


def relative(obj: SceneObject, st: BodyState, ego: Ego) -> Relative:
    """``obj`` in the state ``st`` seen from ``ego`` (the equations of the module docstring)."""
    c, s = ego.cos_yaw, ego.sin_yaw
    dx, dy = st.x_m - ego.front_x_m, st.y_m - ego.front_y_m
    ax, ay = dx * c + dy * s, dy * c - dx * s
    cd, sd = st.cos_h * c + st.sin_h * s, st.sin_h * c - st.cos_h * s
    fore, aft, across = obj.front_m * cd, -obj.back_m * cd, obj.half_width_m * abs(sd)
    return Relative(obj, st, ax + (min(fore, aft) - across), ax + (max(fore, aft) + across), ay + obj.shift_m * sd,
                    obj.half_length_m * abs(sd) + obj.half_width_m * abs(cd), st.vx_mps * c + st.vy_mps * s,
                    sd == 0.0)


class Scene:
    """All objects of a scenario around the ego."""

    def __init__(self, objects: Sequence[SceneObject], ego: EgoBody, radar: RadarConfig, end: EndConfig) -> None:
        self.objects = list(objects)
        self.ego = ego
        self._len, self._half_w = ego.length_m, ego.half_width_m
        self._radar, self._end = radar, end
        self._tan_half_fov = math.tan(math.radians(radar.field_of_view_deg / 2.0))
        self._moved = self._faster = False
        self._states_t_s: float | None = None
        self._states: list[BodyState] = []
        self._seen: tuple[float, Ego | None, list[Relative]] = (math.nan, None, [])

    def __bool__(self) -> bool:
        return bool(self.objects)

    def states(self, t_s: float) -> list[BodyState]:
        """Each object's state at ``t_s``, kept until another time is asked or a trigger fires."""
        if t_s != self._states_t_s:
            self._states = [obj.motion.state(t_s) for obj in self.objects]
            self._states_t_s = t_s
        return self._states

    def seen_from(self, t_s: float, ego: Ego) -> list[Relative]:
        """Every object seen from ``ego`` at ``t_s`` (kept for the same time and ego: a cycle asks four times)."""
        t, last, rel = self._seen
        if t != t_s or last is not ego:
            rel = [relative(obj, st, ego) for obj, st in zip(self.objects, self.states(t_s))]
            self._seen = (t_s, ego, rel)
        return rel

    def _in_path(self, r: Relative) -> bool:
        return r.far_m > -self._len and abs(r.y_c_m) < self._half_w + r.half_y_m

    def path_gap(self, t_s: float, ego: Ego) -> tuple[float, Relative | None]:
        """Gap (m) to the nearest object ahead whose body overlaps the ego's across (inf: none), and that object."""
        best, found = math.inf, None
        for r in self.seen_from(t_s, ego):
            if self._in_path(r) and r.gap_m < best:
                best, found = r.gap_m, r
        return best, found

    def observe(self, t_s: float, ego: Ego) -> float:
        """Once per ECU cycle: fire the triggers; the path gap (m, inf without one)."""
        fired = False
        trigger_ego = self.ego.trigger_state(ego)
        for r in self.seen_from(t_s, ego):
            fired = r.obj.motion.observe(t_s, r.gap_m, trigger_ego) or fired
        if fired:  # a start time changed: the states are worked out again
            self._states_t_s, self._seen = None, (math.nan, None, [])
        return self.path_gap(t_s, ego)[0]

    # -- the radar's object ---------------------------------------------------
    def radar_truth(self, t_s: float, ego: Ego) -> Truth | None:
        """The object the radar reports (see the module docstring), or None."""
        best, best_key = None, None
        for r in self.seen_from(t_s, ego):
            gap = r.gap_m
            if 0.0 < gap <= self._radar.max_range_m and \
                    max(0.0, abs(r.y_c_m) - r.half_y_m) <= gap * self._tan_half_fov:
                key = (not abs(r.y_c_m) - r.half_y_m < LANE_HALF_WIDTH_M, gap)
                if best_key is None or key < best_key:
                    best, best_key = r, key
        if best is None:
            return None
        return Truth(best.gap_m, best.speed_along_mps - ego.vx_mps, best.y_c_m)

    # -- end conditions -------------------------------------------------------
    def end_reason(self, t_s: float, ego: Ego) -> str | None:
        """``standstill`` or ``matched_speed`` when ``[end]`` asks for it and it has happened."""
        end, speed_mps = self._end, ego.speed_mps
        if end.standstill:
            if speed_mps > end.standstill_speed_mps:
                self._moved = True
            elif self._moved:
                return "standstill"
        if end.matched_speed:
            _, r = self.path_gap(t_s, ego)
            if r is not None:
                v_obj = r.speed_along_mps
                if speed_mps > v_obj + end.matched_speed_margin_mps:
                    self._faster = True
                elif self._faster and speed_mps <= v_obj:
                    return "matched_speed"
        return None
