"""Where an object stands in the plane: crd's ``[objects.road_pose]`` or ``[objects.pose]`` from its Init position.

crd places such an object by its box centre (docs/scenario-reference.md); OpenSCENARIO by its
reference point, with the box centre at ``BoundingBox/Center (cx, cy)`` in the entity's frame:

* a ``<RoadPosition>`` or ``<LanePosition>`` on the road that is the scenario's ``[road]``, of an
  object whose box centre is its reference point, is ``road_pose``: ``s``, ``t`` (from the reference
  line, as crd's ``[road]`` has no lane offset: ``t - offset``) and the heading relative to the road's;
* any other position (a ``<RelativeObjectPosition>``, a ``<WorldPosition>`` across the ego's axis),
  or a box centre elsewhere, is ``pose``: the centre ``P + R(h) (cx, cy)`` and the heading, in crd's
  frame (:class:`.frame.Frame`).

The object's Init speed is ``speed_mps`` along its heading. crd's motion keys of a placed object
(braking, lateral motion) run along its heading too, but OpenSCENARIO's story actions for them are
not read here: such an object's story is refused with a one-line error.
"""

from __future__ import annotations

import math
from typing import Any

from .entities import Body
from .frame import Frame
from .opendrive import Road
from .positions import Pose


def placement_keys(body: Body, pose: Pose, frame: Frame, road: Road | None) -> dict[str, Any]:
    """``{"road_pose": ...}`` or ``{"pose": ...}`` for an object standing at ``pose``."""
    spot = pose.spot
    centred = body.centre_x_m == 0.0 and body.centre_y_m == 0.0
    if spot is not None and road is not None and spot.road_id == road.road_id and centred:
        return {"road_pose": {"s_m": spot.s_m, "t_m": spot.t_m - road.lane_offset_m, "heading_rad": spot.h_rel_rad}}
    x, y = world_centre(body, pose)
    return {"pose": {"x_m": frame.along(x, y) - frame.ego_front_m, "y_m": frame.across(x, y) - frame.ego.centre_y_m,
                     "heading_rad": math.remainder(pose.h_rad - frame.pose.h_rad, 2 * math.pi)}}


def world_centre(body: Body, pose: Pose) -> tuple[float, float]:
    """The box centre in world coordinates: ``P + R(h) (cx, cy)``."""
    c, s = math.cos(pose.h_rad), math.sin(pose.h_rad)
    return (pose.x_m + body.centre_x_m * c - body.centre_y_m * s, pose.y_m + body.centre_x_m * s + body.centre_y_m * c)
