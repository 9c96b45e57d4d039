"""Private actions crd reads: teleport, absolute speed, lane change; each a small record.

``<TeleportAction>`` (a :mod:`.positions` position, relative to an entity too), ``<SpeedAction>`` with an
``<AbsoluteTargetSpeed>`` and ``<SpeedActionDynamics>`` (any shape and
dimension here; :mod:`.mapping` decides what crd's profiles can follow), and
``<LaneChangeAction>`` to an absolute or relative target lane. Everything else
``<FollowTrajectoryAction>`` with a polyline (:mod:`.trajectory`). Everything else
under ``<PrivateAction>`` is not supported yet, the other routing actions included.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from .opendrive import Road
from .positions import TELEPORT_POSITIONS, Pose, read_position
from .trajectory import FollowTrajectory, read_follow_trajectory
from .xml_source import Element, attr, child, choice, dispatch, number, one_child, only, unsupported

SHAPES = ("step", "linear", "cubic", "sinusoidal")
DIMENSIONS = ("time", "rate", "distance")


@dataclass(frozen=True)
class Dynamics:
    """A transition: its shape, and ``value`` in the unit of its dimension (s, m/s or m/s^2, m)."""

    shape: str
    dimension: str
    value: float
    elem: Element


@dataclass(frozen=True)
class Teleport:
    pose: Pose
    elem: Element


@dataclass(frozen=True)
class SpeedChange:
    target_mps: float
    dynamics: Dynamics
    elem: Element


@dataclass(frozen=True)
class LaneChange:
    """To lane ``lane`` (absolute), or ``relative`` lanes from ``entity``'s lane; plus ``offset_m``."""

    lane: int | None
    entity: str | None
    relative: int | None
    offset_m: float
    dynamics: Dynamics
    elem: Element


def _dynamics(elem: Element) -> Dynamics:
    only(elem, ())
    return Dynamics(choice(elem, "dynamicsShape", SHAPES), choice(elem, "dynamicsDimension", DIMENSIONS),
                    number(elem, "value"), elem)


def _speed(elem: Element, roads: Mapping[str, Road]) -> SpeedChange:  # noqa: ARG001
    only(elem, ("SpeedActionDynamics", "SpeedActionTarget"))
    target = one_child(child(elem, "SpeedActionTarget"), ("AbsoluteTargetSpeed",))
    only(target, ())
    return SpeedChange(number(target, "value"), _dynamics(child(elem, "SpeedActionDynamics")), elem)


def _longitudinal(elem: Element, roads: Mapping[str, Road]) -> SpeedChange:
    return dispatch(one_child(elem), {"SpeedAction": _speed}, roads)


def _lane_change(elem: Element, roads: Mapping[str, Road]) -> LaneChange:  # noqa: ARG001
    only(elem, ("LaneChangeActionDynamics", "LaneChangeTarget"))
    target = one_child(child(elem, "LaneChangeTarget"), ("AbsoluteTargetLane", "RelativeTargetLane"))
    only(target, ())
    lane = rel = entity = None
    if target.tag == "AbsoluteTargetLane":
        lane = int(number(target, "value"))
    else:
        entity, rel = attr(target, "entityRef"), int(number(target, "value"))
    return LaneChange(lane, entity, rel, number(elem, "targetLaneOffset", 0.0),
                      _dynamics(child(elem, "LaneChangeActionDynamics")), elem)


def _lateral(elem: Element, roads: Mapping[str, Road]) -> LaneChange:
    return dispatch(one_child(elem), {"LaneChangeAction": _lane_change}, roads)


def _teleport(elem: Element, roads: Mapping[str, Road]) -> Teleport:
    only(elem, ("Position",))
    return Teleport(read_position(child(elem, "Position"), roads, TELEPORT_POSITIONS), elem)


def _route(elem: Element, roads: Mapping[str, Road]) -> None:  # noqa: ARG001 - one handler signature
    raise unsupported(elem, "crd's objects follow trajectories (<FollowTrajectoryAction>), not routes")


ROUTING = {"FollowTrajectoryAction": read_follow_trajectory, "AssignRouteAction": _route,
           "AcquirePositionAction": _route}


def _routing(elem: Element, roads: Mapping[str, Road]) -> FollowTrajectory:
    return dispatch(one_child(elem), ROUTING, roads)


PRIVATE_ACTIONS = {"TeleportAction": _teleport, "LongitudinalAction": _longitudinal, "LateralAction": _lateral,
                   "RoutingAction": _routing}


def read_private_action(elem: Element, roads: Mapping[str, Road]) -> Teleport | SpeedChange | LaneChange:
    """One ``<PrivateAction>``."""
    return dispatch(one_child(elem), PRIVATE_ACTIONS, roads)


def read_action(elem: Element, roads: Mapping[str, Road]) -> Teleport | SpeedChange | LaneChange:
    """A story's ``<Action>``: a private action (global and user-defined actions are not supported yet)."""
    attr(elem, "name")
    return dispatch(one_child(elem), {"PrivateAction": read_private_action}, roads)
