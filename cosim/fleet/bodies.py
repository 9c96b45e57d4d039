"""The other vehicles as objects of each vehicle's scene: one board of poses, read through each car's frame.

Every vehicle runs in its own frame (:mod:`cosim.fleet.config`). A :class:`Frame` maps that frame to the
world and back (a rotation by ``heading_rad`` and a shift). The :class:`PoseBoard` holds every vehicle's
body at the last time the lock-step wrote it (every ECU cycle, and every plant step while a contact is
possible): its box centre, heading, velocity over ground and yaw rate, in the world. A
:class:`PuppetMotion` is another vehicle seen from one car: the board's entry brought into that car's frame.
It is a :class:`~cosim.world.scene_objects.Motion`, so the car's radar, 2-D tracks and contact watch see the
other vehicle as they see any moving object; its reference point is the box's centre.

Asked for a time after the board's (never within the lock-step, which writes the board first), the state
is extrapolated at constant velocity; asked for an earlier time, the board's own is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

from ..scenarios.config import ObjectConfig, PlantConfig
from ..world.ego import Ego, EgoBody
from ..world.scene_motion import BodyState
from ..world.scene_objects import SceneObject
from ..world.trajectory import EgoState, Kinematics


@dataclass(frozen=True, slots=True)
class Frame:
    """A vehicle's frame in the world: its origin and the heading of its ``x`` axis."""

    x_m: float
    y_m: float
    heading_rad: float

    def to_world(self, x_m: float, y_m: float) -> tuple[float, float]:
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return self.x_m + x_m * c - y_m * s, self.y_m + x_m * s + y_m * c

    def from_world(self, x_m: float, y_m: float) -> tuple[float, float]:
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        dx, dy = x_m - self.x_m, y_m - self.y_m
        return dx * c + dy * s, dy * c - dx * s

    def rotate_to_world(self, vx: float, vy: float) -> tuple[float, float]:
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return vx * c - vy * s, vx * s + vy * c

    def rotate_from_world(self, vx: float, vy: float) -> tuple[float, float]:
        c, s = math.cos(self.heading_rad), math.sin(self.heading_rad)
        return vx * c + vy * s, vy * c - vx * s


class WorldBody(NamedTuple):
    """A vehicle's box in the world at one time ``t_s``: its centre, heading, velocity over ground, yaw rate and
    speed (:class:`~cosim.world.trajectory.Kinematics`)."""

    t_s: float
    box: Kinematics


def world_body(t_s: float, ego: Ego, body: EgoBody, frame: Frame) -> WorldBody:
    """The box of the vehicle whose ego (in its own frame) is ``ego``, in the world."""
    half = 0.5 * body.length_m
    cx, cy = frame.to_world(ego.front_x_m - half * ego.cos_yaw, ego.front_y_m - half * ego.sin_yaw)
    motion = body.box_motion(ego)
    vx, vy = frame.rotate_to_world(motion.vx_mps, motion.vy_mps)
    return WorldBody(t_s, Kinematics(cx, cy, ego.yaw_rad + frame.heading_rad, vx, vy, motion.yaw_rate_radps,
                                     ego.speed_mps))


class PoseBoard:
    """Every vehicle's :class:`WorldBody` at the last time written (by name)."""

    def __init__(self) -> None:
        self.bodies: dict[str, WorldBody] = {}

    def write(self, name: str, body: WorldBody) -> None:
        self.bodies[name] = body


class PuppetMotion:
    """Vehicle ``name`` on ``board``, seen in ``frame`` (module docstring)."""

    def __init__(self, board: PoseBoard, name: str, frame: Frame) -> None:
        self.board, self.name, self.frame = board, name, frame
        self._cache: tuple[float, WorldBody | None, BodyState | None] = (math.nan, None, None)

    def state(self, t_s: float) -> BodyState:
        entry = self.board.bodies[self.name]
        t, seen, st = self._cache
        if t == t_s and seen is entry and st is not None:
            return st
        dt, body = max(0.0, t_s - entry.t_s), entry.box
        x, y = self.frame.from_world(body.x_m + body.vx_mps * dt, body.y_m + body.vy_mps * dt)
        vx, vy = self.frame.rotate_from_world(body.vx_mps, body.vy_mps)
        yaw = body.yaw_rad + body.yaw_rate_radps * dt - self.frame.heading_rad
        st = BodyState(x, y, yaw, math.cos(yaw), math.sin(yaw), vx, vy, body.yaw_rate_radps, body.speed_mps)
        self._cache = (t_s, entry, st)
        return st

    def observe(self, t_s: float, gap_m: float, ego: EgoState) -> bool:
        return False  # another car has no triggers: it is driven by its own driver


def vehicle_object(index: int, name: str, plant: PlantConfig, motion: PuppetMotion) -> SceneObject:
    """Another vehicle as a scene object: its plant's box, size class ``car``, reference point the centre."""
    cfg = ObjectConfig(name=name, length_m=plant.length_m, width_m=plant.width_m, position_m=0.0)
    return SceneObject(index, cfg, motion, plant.length_m / 2.0, size_class="car")
