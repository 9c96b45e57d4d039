"""Contact between the ego and the scene's objects: a cheap look-ahead per cycle, the exact test per plant step.

The master steps the plant a whole ECU cycle at once unless a contact is possible within it
(:meth:`ContactWatch.candidates`, conservative); then it steps 1 ms at a time and tests the
candidates at every step (:meth:`ContactWatch.contact`): the separating-axis test of
:mod:`cosim.world.scene` (on the ego's axes with the 1-D world's boundaries, on the object's own
axes when it is turned against the ego). A hit records where and how hard (:class:`Hit`): the
contact point and normal of the boxes at this step and the step before
(:func:`~cosim.world.geometry.swept_contact`), the closing speed along the ego's heading (the 1-D
world's relative impact speed, and Euro NCAP's with the target's velocity along the ego's heading)
and along the contact normal (:func:`~cosim.world.geometry.impact_speed_mps`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from .ego import Ego
from .geometry import TOUCH_TOL_M, BodyMotion, Box, Contact, axis_overlaps, impact_speed_mps, swept_contact
from .scene import Relative, Scene, relative
from .scene_motion import BodyState
from .scene_objects import SceneObject

_ACCEL_BOUND_MPS2 = 50.0  # no body changes speed faster than this within a cycle (the look-ahead's slack)


class Hit(NamedTuple):
    """A contact: time (s), the object, its gap (m, <= 0), the closing speed along the ego's heading (m/s),
    the contact point (m), the unit normal from the ego to the object, the closing speed along it (m/s)."""

    t_s: float
    obj: SceneObject
    gap_m: float
    impact_speed_mps: float
    x_m: float
    y_m: float
    normal: tuple[float, float]
    normal_speed_mps: float

    def as_dict(self) -> dict:
        """What ``metrics.json`` (``contact``) and the ``collision`` event record of a planar run."""
        return {"t_s": self.t_s, "object": self.obj.index, "object_name": self.obj.name, "x_m": self.x_m,
                "y_m": self.y_m, "normal": list(self.normal), "impact_speed_mps": self.impact_speed_mps,
                "normal_speed_mps": self.normal_speed_mps}


def object_box(obj: SceneObject, st: BodyState) -> Box:
    cx, cy = obj.centre(st)
    return Box(cx, cy, st.yaw_rad, obj.length_m, obj.width_m)


def object_motion(obj: SceneObject, st: BodyState) -> BodyMotion:
    """The velocity over ground of the box's centre, and the yaw rate."""
    r, w = 0.5 * (obj.front_m - obj.back_m), st.yaw_rate_radps
    return BodyMotion(st.vx_mps - w * r * st.sin_h, st.vy_mps + w * r * st.cos_h, w)


class ContactWatch:
    """The look-ahead and the per-step test for one scene (it keeps the last step tested, for the normal)."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self._len, self._half_w = scene.ego.length_m, scene.ego.half_width_m
        self._watched: list[SceneObject] = []
        self._before: tuple[float, Ego] | None = None

    def candidates(self, t_s: float, ego: Ego, span_s: float) -> bool:
        """Whether any body could touch the ego within ``span_s`` after ``t_s`` (conservative); remembers which.

        Per object, every interval of the test is widened by how far the two bodies can move against each
        other within the span: relative speed, a 50 m/s^2 bound on speed changes, and what the rotations of
        both sweep (yaw rate times the distance of the object's far end from the bumper).
        """
        slack = 0.5 * _ACCEL_BOUND_MPS2 * span_s * span_s + 0.01
        vex, vey = self.scene.ego.velocity(ego)
        self._watched = []
        for r in self.scene.seen_from(t_s, ego):
            st = r.state
            turn = abs(ego.yaw_rate_radps) * (abs(r.far_m) + abs(r.y_c_m) + r.half_y_m) \
                + abs(st.yaw_rate_radps) * r.obj.length_m
            reach = (math.hypot(vex - st.vx_mps, vey - st.vy_mps) + turn) * span_s + slack
            if r.gap_m <= reach and r.far_m >= -self._len - reach and \
                    abs(r.y_c_m) - (self._half_w + r.half_y_m) <= reach:
                self._watched.append(r.obj)
        self._before = (t_s, ego)
        return bool(self._watched)

    def _touches(self, r: Relative, ego_box: Box | None, ego: Ego) -> bool:
        if not (r.gap_m <= 0.0 and r.far_m > -self._len and abs(r.y_c_m) < self._half_w + r.half_y_m):
            return False
        if r.aligned:
            return True
        o = axis_overlaps(ego_box or self.scene.ego.box(ego), object_box(r.obj, r.state))
        return o[2] >= -TOUCH_TOL_M and o[3] >= -TOUCH_TOL_M

    def contact(self, t_s: float, ego: Ego) -> Hit | None:
        """The first watched object (in scene order) touching ``ego`` at ``t_s``, else None."""
        for obj in self._watched:  # only the watched objects' states: the others cannot touch within the cycle
            r = relative(obj, obj.motion.state(t_s), ego)
            if self._touches(r, None, ego):
                return self._hit(t_s, ego, r)
        self._before = (t_s, ego)
        return None

    def _hit(self, t_s: float, ego: Ego, r: Relative) -> Hit:
        body, obj = self.scene.ego, r.obj
        after = (body.box(ego), object_box(obj, r.state))
        t0, ego0 = self._before if self._before is not None else (t_s, ego)
        before = (body.box(ego0), object_box(obj, obj.motion.state(t0)))
        where = swept_contact(before, after)
        if where is None:  # touching on the 1-D boundaries but not within the box test's tolerance: the front
            front = (ego.front_x_m, ego.front_y_m)
            point, normal = front, (ego.cos_yaw, ego.sin_yaw)
        else:
            point, normal = (where.x_m, where.y_m), (where.normal_x, where.normal_y)
        normal_speed = impact_speed_mps(Contact(*point, *normal, 0.0), after[0], body.box_motion(ego), after[1],
                                        object_motion(obj, r.state))
        return Hit(t_s, obj, r.gap_m, ego.vx_mps - r.speed_along_mps, point[0], point[1], normal, normal_speed)
