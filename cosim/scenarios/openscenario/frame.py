"""crd's 1-D frame from the ego's start pose, and the entities' places and speeds in it.

Origin: the ego's reference point at t = 0; ``along`` on its heading, ``across``
to its left (ASAM OpenSCENARIO 1.x world frame, x forward, y left):

    along  =  (x - x_e) cos h_e + (y - y_e) sin h_e
    across = -(x - x_e) sin h_e + (y - y_e) cos h_e

An object heading with the ego (``dir = +1``) or against it (``dir = -1``, an
oncoming object: negative ``speed_mps``) is supported; any other heading needs
the planar world. crd's ``position_m`` is the object's rear (lowest ``along``
of its box) ahead of the ego's front bumper; ``lateral_m`` its box centre's
``across`` minus the ego's box centre's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .entities import Body
from .opendrive import PLANAR
from .positions import Pose
from .xml_source import Element, unsupported

HEADING_TOL_RAD = 1e-6


@dataclass(frozen=True)
class Frame:
    ego: Body
    pose: Pose

    def along(self, x_m: float, y_m: float) -> float:
        h = self.pose.h_rad
        return (x_m - self.pose.x_m) * math.cos(h) + (y_m - self.pose.y_m) * math.sin(h)

    def across(self, x_m: float, y_m: float) -> float:
        h = self.pose.h_rad
        return -(x_m - self.pose.x_m) * math.sin(h) + (y_m - self.pose.y_m) * math.cos(h)

    def aligned(self, h_rad: float) -> int | None:
        """+1 along the ego's heading, -1 against it, None across it."""
        diff = math.remainder(h_rad - self.pose.h_rad, 2 * math.pi)
        if abs(diff) <= HEADING_TOL_RAD:
            return 1
        if abs(abs(diff) - math.pi) <= HEADING_TOL_RAD:
            return -1
        return None

    def direction(self, h_rad: float, elem: Element) -> int:
        """+1 along the ego's heading, -1 against it."""
        aligned = self.aligned(h_rad)
        if aligned is None:
            raise unsupported(elem, f"heading {h_rad:g} rad across the ego's {self.pose.h_rad:g} rad; {PLANAR}")
        return aligned

    @property
    def ego_front_m(self) -> float:
        return self.ego.front_m

    def rear_offset_m(self, body: Body, direction: int) -> float:
        """The body's rear (lowest along) relative to its reference point, along the frame."""
        return direction * body.centre_x_m - body.length_m / 2

    def rear_m(self, body: Body, pose: Pose, direction: int) -> float:
        """crd's ``position_m``: the body's rear ahead of the ego's front bumper."""
        return (self.along(pose.x_m, pose.y_m) + self.rear_offset_m(body, direction)) - self.ego_front_m

    def lateral_m(self, body: Body, pose: Pose, direction: int) -> float:
        """crd's ``lateral_m``: the body's centre left of the ego's centre line."""
        return (self.across(pose.x_m, pose.y_m) + direction * body.centre_y_m) - self.ego.centre_y_m
