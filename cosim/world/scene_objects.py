"""Objects at run time: a box, a motion and the triggers that start it.

Two motions, each giving a :class:`~cosim.world.scene_motion.BodyState` at any time (closed form,
so the run is the same whatever the step pattern):

* :class:`PathMotion`: the 1-D profiles (:mod:`cosim.world.scene_motion`) in the object's frame,
  reference point the rear; its gap triggers (``brake_at_gap_m``, ``lateral_at_gap_m``) fire on the
  ego's gap to it;
* :class:`BehaviourMotion`: a path, a speed profile and a trigger (:mod:`cosim.world.trajectory`),
  reference point the box's centre; its trigger fires on the ego's pose and speed.

Both are observed once per ECU cycle, as the loop samples the ego; a trigger fires at the first
sample at which it holds.
"""

from __future__ import annotations

import math
from typing import Protocol

from ..scenarios.config import ObjectConfig
from .scene_motion import BodyState, motions
from .targets import TARGET_CLASSES
from .trajectory import Behaviour, BehaviourState, EgoState, advance, initial_state, kinematics


class Motion(Protocol):
    """How an object moves: its state at a time, and the triggers it fires when the ego is sampled."""

    def state(self, t_s: float) -> BodyState: ...

    def observe(self, t_s: float, gap_m: float, ego: EgoState) -> bool:
        """Fire the triggers that hold (once each); whether one fired."""


class PathMotion:
    """The 1-D motion of ``[object]`` in the frame ``origin`` = (x, y, heading) of its rear at t = 0.

    ``origin`` None: the world's own frame (the 1-D path), where the profiles give the rear's x and y
    directly, with no arithmetic in between.
    """

    def __init__(self, cfg: ObjectConfig, origin: tuple[float, float, float] | None = None) -> None:
        self.cfg = cfg
        self.lon, self.lat = motions(cfg, 0.0, 0.0) if origin is not None else motions(cfg)
        self._origin = origin
        self._cos, self._sin = (1.0, 0.0) if origin is None else (math.cos(origin[2]), math.sin(origin[2]))
        self.brake_t_s: float | None = cfg.brake_at_s
        self.lateral_t_s: float | None = cfg.lateral_at_s
        # standing, with no lateral motion: the profiles give the same state at every time (rear0 + 0.0 t is
        # rear0, to the bit), worked out once
        still = cfg.speed_mps == 0.0 and (cfg.lateral_end_m is None or cfg.lateral_speed_mps == 0.0)
        self._still = self._state(0.0) if still else None

    def state(self, t_s: float) -> BodyState:
        return self._still if self._still is not None else self._state(t_s)

    def _state(self, t_s: float) -> BodyState:
        along, v = self.lon.state(t_s, self.brake_t_s)
        across, v_across = self.lat.state(t_s, self.lateral_t_s)
        if self._origin is None:
            return BodyState(along, across, 0.0, 1.0, 0.0, v, v_across, 0.0, v)
        (x0, y0, h), c, s = self._origin, self._cos, self._sin
        return BodyState(x0 + along * c - across * s, y0 + along * s + across * c, h, c, s,
                         v * c - v_across * s, v * s + v_across * c, 0.0, v)

    def observe(self, t_s: float, gap_m: float, ego: EgoState) -> bool:
        """Fire the gap triggers (once) when the ego's gap has fallen to them."""
        c, fired = self.cfg, False
        if self.brake_t_s is None and c.brake_at_gap_m is not None and gap_m <= c.brake_at_gap_m:
            self.brake_t_s, fired = t_s, True
        if self.lateral_t_s is None and c.lateral_at_gap_m is not None and gap_m <= c.lateral_at_gap_m:
            self.lateral_t_s, fired = t_s, True
        return fired


class BehaviourMotion:
    """A :class:`~cosim.world.trajectory.Behaviour`: the box's centre along a path, started by a trigger."""

    def __init__(self, behaviour: Behaviour) -> None:
        self.behaviour = behaviour
        self.started: BehaviourState = initial_state(behaviour)
        self._waiting = self._state(0.0) if self.started.started_at_s is None else None  # at rest until it starts

    def state(self, t_s: float) -> BodyState:
        if self.started.started_at_s is None:
            return self._waiting
        return self._state(t_s)

    def _state(self, t_s: float) -> BodyState:
        k = kinematics(self.behaviour, self.started, t_s)
        return BodyState(k.x_m, k.y_m, k.yaw_rad, math.cos(k.yaw_rad), math.sin(k.yaw_rad), k.vx_mps, k.vy_mps,
                         k.yaw_rate_radps, k.speed_mps)

    def observe(self, t_s: float, gap_m: float, ego: EgoState) -> bool:
        before = self.started
        self.started = advance(self.behaviour, before, t_s, ego)
        return self.started is not before


class SceneObject:
    """One object: its name, box (m), radar size class and motion.

    The box reaches ``front_m`` ahead of the reference point along the heading and ``back_m`` behind it
    (the rear as reference: ``back_m`` = 0, exactly). ``size_class``: what the radar reports when the object is
    not a protocol target (another vehicle of a fleet: ``car``); else the target class's.
    """

    def __init__(self, index: int, cfg: ObjectConfig, motion: Motion, front_m: float,
                 size_class: str | None = None) -> None:
        self.index, self.cfg, self.name, self.motion = index, cfg, cfg.name, motion
        self.length_m, self.width_m = cfg.length_m, cfg.width_m
        self.front_m, self.back_m = front_m, cfg.length_m - front_m
        self.half_length_m, self.half_width_m = 0.5 * cfg.length_m, cfg.width_m / 2.0
        self.shift_m = 0.5 * (self.front_m - self.back_m)  # reference point -> the box's centre, along the heading
        target = TARGET_CLASSES.get(cfg.target_class or "")
        self.kind = cfg.target_class or size_class or "object"
        self.size_class = size_class or (target.size_class if target is not None else "unknown")

    def centre(self, st: BodyState) -> tuple[float, float]:
        """The box's centre (m) in the state ``st``."""
        return st.x_m + self.shift_m * st.cos_h, st.y_m + self.shift_m * st.sin_h
