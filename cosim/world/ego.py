"""The ego car in the world: its pose, front bumper and velocity from the plant's outputs.

The plant reports a pose point (builtin: the centre of gravity; ``x``, ``y``, ``yaw``) and the
1-D world took its ``position`` output plus ``[plant] front_bumper_offset_m`` as the front bumper
(the builtin plant's ``x`` starts at 0, where the bumper starts). Both hold in one frame: the world
frame is the 1-D path frame, in which the pose point sits ``d = [plant] cg_to_front_m`` behind the
front bumper, so (``o`` the offset, ``ψ`` the yaw)::

    front = (x + o + d (cos ψ - 1),  y + d sin ψ)        pose point = (x + o - d,  y)

written so that with ``ψ = 0`` (every 1-D plant, and ours with the wheel straight) the front is
``x + o`` to the last bit, as it always was. A plant without ``y``, ``yaw``, ``yaw_rate``, ``vx``,
``vy`` outputs has them 0, 0, 0, its speed, 0 (:class:`~cosim.world.plant_fmu.PlantSample`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ..scenarios.config import PlantConfig
from .geometry import BodyMotion, Box
from .plant_fmu import PlantPose, PlantSample
from .trajectory import EgoState


class Ego(NamedTuple):
    """The ego at one instant (m, rad, m/s, rad/s): front bumper centre, heading, pose point, velocity.

    ``vx_mps``, ``vy_mps`` are the pose point's velocity in the vehicle frame (forward, left);
    ``position_m`` is the plant's position output (the 1-D coordinate the scripted driver reads).
    """

    front_x_m: float
    front_y_m: float
    yaw_rad: float
    cos_yaw: float
    sin_yaw: float
    x_m: float
    y_m: float
    speed_mps: float
    vx_mps: float
    vy_mps: float
    yaw_rate_radps: float
    position_m: float


class EgoBody:
    """The ego's box and the frame arithmetic of the module docstring, fixed at start-up."""

    def __init__(self, plant: PlantConfig) -> None:
        self.length_m, self.width_m = plant.length_m, plant.width_m
        self.half_width_m = plant.width_m / 2.0
        self.front_m = plant.front_m  # pose point -> front bumper
        self._offset_m = plant.front_bumper_offset_m

    def at(self, p: PlantPose | PlantSample) -> Ego:
        """The ego whose plant reports the outputs ``p`` (SI)."""
        yaw = p.yaw_rad
        c, s, d = math.cos(yaw), math.sin(yaw), self.front_m
        front_x = p.position_m + self._offset_m + d * (c - 1.0)
        return Ego(front_x, p.y_m + d * s, yaw, c, s, p.position_m + self._offset_m - d, p.y_m, p.speed_mps, p.vx_mps,
                   p.vy_mps, p.yaw_rate_radps, p.position_m)

    def box(self, ego: Ego) -> Box:
        """The ego's box: ``length_m`` back from the front bumper, ``width_m`` across."""
        half = 0.5 * self.length_m
        return Box(ego.front_x_m - half * ego.cos_yaw, ego.front_y_m - half * ego.sin_yaw, ego.yaw_rad,
                   self.length_m, self.width_m)

    @staticmethod
    def velocity(ego: Ego) -> tuple[float, float]:
        """The pose point's velocity over ground in world axes (m/s)."""
        c, s = ego.cos_yaw, ego.sin_yaw
        return ego.vx_mps * c - ego.vy_mps * s, ego.vx_mps * s + ego.vy_mps * c

    def box_motion(self, ego: Ego) -> BodyMotion:
        """The velocity over ground (world axes) of the box's centre, and the yaw rate."""
        (vx, vy), w = self.velocity(ego), ego.yaw_rate_radps
        r = self.front_m - 0.5 * self.length_m  # pose point -> box centre, along the heading
        return BodyMotion(vx - w * r * ego.sin_yaw, vy + w * r * ego.cos_yaw, w)

    @staticmethod
    def trigger_state(ego: Ego) -> EgoState:
        """What the objects' triggers see: the front bumper centre, heading and speed."""
        return EgoState(ego.front_x_m, ego.front_y_m, ego.yaw_rad, ego.speed_mps)
