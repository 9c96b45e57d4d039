"""An OpenDRIVE road as the ``[road]`` of a planar crd scenario, in crd's frame.

crd's world frame (docs/scenario-reference.md) has the ego's front bumper at the origin at t = 0,
``x`` on its heading and ``y`` to its left; the file's frame is turned and moved onto it
(:class:`.frame.Frame`): a world point ``P`` is at ``x = along(P) - front``,
``y = across(P) - c_y`` (``front``: the ego's front bumper ahead of its reference point; ``c_y``:
its box centre left of it), and a heading ``h`` at ``h - h_ego``. The reference line's pieces map
one to one (:mod:`.plan_view`), so the line is the file's, turned and moved. Lanes: one section of
constant widths, outward from the reference line; a straight road's constant lane offset moves
the line, and one on a curved road is refused in :mod:`.opendrive`.

Without a ``steering`` key in its ``crd_driver`` controller, the ego keeps its start lane
(``[driver.steering] model = "path_following"``): OpenSCENARIO's default controller follows the
lane, and a hold-speed driver would leave a curved road.
"""

from __future__ import annotations

import math
from typing import Any

from ...world.road import LaneSection
from ...world.road import Road as WorldRoad
from .frame import Frame
from .opendrive import Road
from .positions import Pose
from .xml_source import Element, fail, unsupported


def _widths(road: Road, sign: int, where: Element) -> list[float]:
    ids = sorted((k for k in road.lane_width_m if k * sign > 0), key=abs)
    if ids != [sign * (i + 1) for i in range(len(ids))]:
        raise fail(where, f"road {road.road_id!r}: lanes {ids} are not numbered 1, 2, ... outward")
    return [road.lane_width_m[k] for k in ids]


def road_keys(road: Road, frame: Frame, where: Element) -> dict[str, Any]:
    """The ``[road]`` table of a road, in crd's frame."""
    x, y = road.point(0.0, road.lane_offset_m)  # a straight road's lane offset moves its line; a curved one has none
    return {"x_m": frame.along(x, y) - frame.ego_front_m,
            "y_m": frame.across(x, y) - frame.ego.centre_y_m,
            "heading_rad": math.remainder(road.hdg_rad - frame.pose.h_rad, 2 * math.pi),
            "geometry": [dict(g) for g in road.geometry],
            "lane_sections": [{"s_m": 0.0, "left_m": _widths(road, 1, where), "right_m": _widths(road, -1, where)}]}


def ego_lane(road: Road, pose: Pose, where: Element) -> int:
    """The lane the ego starts in, one it drives along the reference line (right-hand traffic)."""
    section = LaneSection.uniform(0.0, tuple(_widths(road, 1, where)), tuple(_widths(road, -1, where)))
    world = WorldRoad(road.plan, (section,))
    s_m, t_m = world.to_st(pose.x_m, pose.y_m)
    lane = world.lane_at(s_m, t_m - road.lane_offset_m)
    if lane is None or lane > 0:
        raise unsupported(where, f"the ego off the right lanes of the curved road {road.road_id!r} (lane {lane}): "
                                 "crd's path-following driver keeps a lane along the reference line")
    return lane
