"""The scene: every object around the ego, contact, the radar's choice of object, end conditions.

Geometry (path coordinates: ``x`` along the path, ``y`` across it, left
positive). The ego occupies ``[bumper - length_m, bumper]`` by ``±width_m/2``;
an object ``[rear, rear + length_m]`` by ``lateral ± width_m/2``. Contact
needs BOTH a longitudinal and a lateral overlap (a car parked in the next
lane is passed, not hit). The relative impact speed is the longitudinal
closing speed ``v_ego - v_obj`` at the first plant step with contact.

Triggers (``brake_at_gap_m``, ``lateral_at_gap_m``) are checked once per ECU
cycle against the object's gap ``rear - bumper``; time triggers are exact.

The radar reports ONE object (the DBC has one ``ObjectTrack``): among the
objects ahead (gap > 0), within ``max_range_m`` and inside the field of view
(the body's nearest point within ``±field_of_view_deg/2`` of the bore
sight), the nearest one whose body reaches into the ego's lane corridor
(``|y| - w/2 < LANE_HALF_WIDTH_M``), else the nearest visible one. This is
the "closest in-path object" choice of a production radar's object selection:
the in-lane target is never hidden behind an object beside the lane, and an
object beside the lane is still reported when nothing is in it, so that the
ECU's own relevance check (``ObjectLateral``, ``ecu/core/relevance.py``)
decides. ``ObjectLateral`` is the object's centre offset ``y``.
"""

from __future__ import annotations

import math
from operator import itemgetter
from typing import NamedTuple, Sequence

from ..scenarios.config import EndConfig, ObjectConfig, PlantConfig, RadarConfig
from .scene_motion import Lateral, Longitudinal, motions

#: half of a 3.5 m lane: the radar's in-lane corridor for its object selection ([M], class value).
LANE_HALF_WIDTH_M = 1.75
_LANE_THEN_GAP = itemgetter(0, 1)  # the radar's choice: in-lane objects first, then the nearest
_ACCEL_BOUND_MPS2 = 50.0  # no body changes speed faster than this within a cycle (contact look-ahead)


class Truth(NamedTuple):
    """What the radar sees of the chosen object: gap (m), range rate (m/s), centre offset (m).

    Immutable; a ``NamedTuple`` rather than a frozen dataclass because one is built every
    cycle: 0.26 instead of 0.56 µs (timeit).
    """

    gap_m: float
    range_rate_mps: float
    lateral_m: float


class SceneObject:
    """One object at run time: its profiles and the trigger times that have fired."""

    def __init__(self, cfg: ObjectConfig) -> None:
        self.cfg = cfg
        self.lon: Longitudinal
        self.lat: Lateral
        self.lon, self.lat = motions(cfg)
        self.brake_t_s: float | None = cfg.brake_at_s
        self.lateral_t_s: float | None = cfg.lateral_at_s

    def arm(self, t_s: float, gap_m: float) -> bool:
        """Fire the gap triggers (once) when the ego's gap has fallen to them; whether one fired."""
        c, fired = self.cfg, False
        if self.brake_t_s is None and c.brake_at_gap_m is not None and gap_m <= c.brake_at_gap_m:
            self.brake_t_s, fired = t_s, True
        if self.lateral_t_s is None and c.lateral_at_gap_m is not None and gap_m <= c.lateral_at_gap_m:
            self.lateral_t_s, fired = t_s, True
        return fired

    def lon_state(self, t_s: float) -> tuple[float, float]:
        return self.lon.state(t_s, self.brake_t_s)

    def lat_state(self, t_s: float) -> tuple[float, float]:
        return self.lat.state(t_s, self.lateral_t_s)


class Scene:
    """All objects of a scenario around an ego of the plant's length and width."""

    def __init__(self, objects: Sequence[ObjectConfig], plant: PlantConfig, radar: RadarConfig,
                 end: EndConfig) -> None:
        self.objects = [SceneObject(o) for o in objects if o.enabled]
        self._len, self._half_w = plant.length_m, plant.width_m / 2.0
        self._radar, self._end = radar, end
        self._tan_half_fov = math.tan(math.radians(radar.field_of_view_deg / 2.0))
        self._moved = self._faster = False
        self._states_t_s: float | None = None
        self._states: list[tuple[SceneObject, float, float, float, float]] = []

    def __bool__(self) -> bool:
        return bool(self.objects)

    def states(self, t_s: float) -> list[tuple[SceneObject, float, float, float, float]]:
        """Each object with its (rear (m), speed (m/s), centre offset (m), lateral speed (m/s)) at ``t_s``.

        Computed once per time and kept until another time is asked or a trigger fires: one
        cycle asks at its time four times (observe, radar_truth, end_reason, may_contact). With
        the Truth record and the written-out tests below, those four took 3.05 µs a cycle before
        and 2.30 µs after (paper scenario, one object, min of 7).
        """
        if t_s != self._states_t_s:
            self._states = [(obj, *obj.lon.state(t_s, obj.brake_t_s), *obj.lat.state(t_s, obj.lateral_t_s))
                            for obj in self.objects]
            self._states_t_s = t_s
        return self._states

    # -- geometry -------------------------------------------------------------
    def _lateral_overlap(self, obj: SceneObject, y_m: float) -> bool:
        return abs(y_m) < self._half_w + obj.cfg.width_m / 2.0

    def path_gap(self, t_s: float, bumper_m: float) -> tuple[float, SceneObject | None]:
        """Gap (m) to the nearest object ahead whose body overlaps the ego's laterally (inf: none)."""
        best, found = math.inf, None
        for obj, rear, _, y, _ in self.states(t_s):
            if rear + obj.cfg.length_m <= bumper_m - self._len:
                continue  # passed
            if abs(y) < self._half_w + obj.cfg.width_m / 2.0 and rear - bumper_m < best:  # _lateral_overlap
                best, found = rear - bumper_m, obj
        return best, found

    def observe(self, t_s: float, bumper_m: float) -> float:
        """Once per ECU cycle: fire the gap triggers; the path gap (m, inf without one)."""
        fired = False
        for obj, rear, _, _, _ in self.states(t_s):
            fired = obj.arm(t_s, rear - bumper_m) or fired
        if fired:
            self._states_t_s = None  # a trigger time changed: the states are worked out again
        return self.path_gap(t_s, bumper_m)[0]

    # -- the radar's object ---------------------------------------------------
    def radar_truth(self, t_s: float, bumper_m: float, speed_mps: float) -> Truth | None:
        """The object the radar reports (see the module docstring), or None."""
        seen = []
        for obj, rear, v, y, _ in self.states(t_s):
            gap, half_width = rear - bumper_m, obj.cfg.width_m / 2.0
            # visible: ahead, within range, its nearest point inside the field of view
            if 0.0 < gap <= self._radar.max_range_m and max(0.0, abs(y) - half_width) <= gap * self._tan_half_fov:
                in_lane = abs(y) - half_width < LANE_HALF_WIDTH_M
                seen.append((not in_lane, gap, Truth._make((gap, v - speed_mps, y))))
        if len(seen) == 1:  # the common case: min() would return it
            return seen[0][2]
        return min(seen, key=_LANE_THEN_GAP)[2] if seen else None

    # -- contact --------------------------------------------------------------
    def may_contact(self, t_s: float, bumper_m: float, speed_mps: float, span_s: float) -> bool:
        """Whether any body could come into contact within the next ``span_s`` (cheap, conservative)."""
        slack = 0.5 * _ACCEL_BOUND_MPS2 * span_s * span_s + 0.01
        for obj, rear, v, y, vy in self.states(t_s):
            reach = abs(speed_mps - v) * span_s + slack
            lon = rear - bumper_m <= reach and rear + obj.cfg.length_m >= bumper_m - self._len - reach
            lat = abs(y) - (self._half_w + obj.cfg.width_m / 2.0) <= abs(vy) * span_s + 0.01
            if lon and lat:
                return True
        return False

    def contact(self, t_s: float, bumper_m: float) -> tuple[SceneObject, float] | None:
        """The object in contact with the ego at ``t_s`` and its gap (m), or None."""
        for obj, rear, _, y, _ in self.states(t_s):
            lon = rear - bumper_m <= 0.0 and rear + obj.cfg.length_m > bumper_m - self._len
            if lon and self._lateral_overlap(obj, y):
                return obj, rear - bumper_m
        return None

    # -- end conditions -------------------------------------------------------
    def end_reason(self, t_s: float, bumper_m: float, speed_mps: float) -> str | None:
        """``standstill`` or ``matched_speed`` when ``[end]`` asks for it and it has happened."""
        end = self._end
        if end.standstill:
            if speed_mps > end.standstill_speed_mps:
                self._moved = True
            elif self._moved:
                return "standstill"
        if end.matched_speed:
            _, obj = self.path_gap(t_s, bumper_m)
            if obj is not None:
                v_obj = obj.lon_state(t_s)[1]
                if speed_mps > v_obj + end.matched_speed_margin_mps:
                    self._faster = True
                elif self._faster and speed_mps <= v_obj:
                    return "matched_speed"
        return None
