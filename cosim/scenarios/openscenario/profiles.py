"""An object's story events as crd's motion keys (``brake_*``, ``lateral_*``) and their triggers.

crd's objects (:mod:`cosim.world.scene_motion`) move at constant speed, brake
once down to a lower speed, and move across once at a constant lateral speed;
each profile starts at a time or when the ego's gap falls to a value. So:

* a ``<SpeedAction>`` with a ``linear`` shape to a lower absolute speed ``v1``
  maps to ``brake_decel_mps2``: ``rate`` gives it, ``time`` T gives
  ``(v0 - v1) / T``, ``distance`` d gives ``(v0^2 - v1^2) / (2 d)``;
  ``brake_to_speed_mps = v1``. Other shapes, a rise in speed, or a second speed
  action are not supported yet;
* a ``<LaneChangeAction>`` with a ``linear`` shape maps to ``lateral_end_m`` (the
  target lane's centre plus ``targetLaneOffset``, in crd's frame) and
  ``lateral_speed_mps``: ``rate`` gives it, ``time`` T gives ``|end - start| / T``,
  ``distance`` d gives ``|end - start| |v0| / d``;
* start conditions (:mod:`.conditions`) between the ego and the acting object:
  simulation time -> ``*_at_s``; relative distance -> ``*_at_gap_m`` (reference
  points converted to bumpers when ``freespace="false"``); time to collision
  -> ``*_at_gap_m = ttc * (v_ego0 - v_obj0)`` (exact while both keep their start
  speeds until then); the object reaching a position -> ``*_at_s`` from its
  constant start speed; the ego reaching a position next to a standing object -> ``*_at_gap_m``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from .actions import Dynamics, LaneChange, SpeedChange
from .conditions import AtDistance, AtPosition, AtTime, AtTravel, AtTtc, AtTtcPoint
from .entities import Body
from .frame import Frame
from .opendrive import Road
from .positions import Pose
from .xml_source import fail, unsupported


@dataclass(frozen=True)
class Actor:
    """An object at t = 0 in crd's frame, with what its triggers need."""

    body: Body
    pose: Pose
    direction: int
    speed_mps: float  #: signed, along the frame
    frame: Frame
    ego_speed_mps: float

    @property
    def rear_m(self) -> float:
        return self.frame.rear_m(self.body, self.pose, self.direction)

    @property
    def lateral_m(self) -> float:
        return self.frame.lateral_m(self.body, self.pose, self.direction)


def _linear(dyn: Dynamics) -> None:
    if dyn.shape != "linear":
        raise unsupported(dyn.elem, f"dynamicsShape={dyn.shape!r} in the story: crd's profiles are linear")
    if dyn.value <= 0.0:
        raise fail(dyn.elem, f"value: expected > 0, got {dyn.value}")


def _gap_from_reference(actor: Actor, distance_m: float, freespace: bool) -> float:
    if freespace:
        return distance_m
    return distance_m + actor.frame.rear_offset_m(actor.body, actor.direction) - actor.frame.ego_front_m


def _pair(cond: AtDistance | AtTtc, actor: Actor, ego: str) -> None:
    if {cond.entity, cond.other} != {ego, actor.body.name}:
        raise unsupported(cond.elem, f"a condition between {cond.entity!r} and {cond.other!r}: crd's triggers are the "
                                     f"ego's gap to the acting object ({actor.body.name!r})")


def trigger(cond: Any, actor: Actor, ego: str) -> tuple[str, float]:
    """``("at_s", t)`` or ``("at_gap_m", gap)`` for a start condition."""
    if isinstance(cond, AtTime):
        return "at_s", cond.t_s
    if isinstance(cond, AtDistance):
        _pair(cond, actor, ego)
        return "at_gap_m", _gap_from_reference(actor, cond.value_m, cond.freespace)
    if isinstance(cond, AtTtc):
        _pair(cond, actor, ego)
        closing = actor.ego_speed_mps - actor.speed_mps
        if closing <= 0.0:
            raise fail(cond.elem, f"time to collision with a closing speed of {closing:g} m/s: never reached")
        return "at_gap_m", _gap_from_reference(actor, cond.ttc_s * closing, cond.freespace)
    if isinstance(cond, AtTtcPoint):
        raise unsupported(cond.elem, "a time to collision with a position to start a speed or lane change: crd "
                                     "starts a trajectory so, these by time or the ego's gap")
    if isinstance(cond, AtTravel):
        raise unsupported(cond.elem, "a travelled distance to start a brake or lane change: crd reads one for a "
                                     "speed change along a trajectory")
    return _reach(cond, actor, ego)


def _reach(cond: AtPosition, actor: Actor, ego: str) -> tuple[str, float]:
    target = actor.frame.along(cond.pose.x_m, cond.pose.y_m)
    if cond.entity == actor.body.name:
        start = actor.frame.along(actor.pose.x_m, actor.pose.y_m)
        if actor.speed_mps == 0.0 or (target - start) / actor.speed_mps < 0.0:
            raise fail(cond.elem, f"{actor.body.name!r} never reaches the position at {actor.speed_mps:g} m/s")
        return "at_s", (target - start) / actor.speed_mps
    if cond.entity == ego and actor.speed_mps == 0.0:
        return "at_gap_m", actor.rear_m - (target + actor.frame.ego_front_m)
    raise unsupported(cond.elem, f"{cond.entity!r} reaching a position to start {actor.body.name!r}: crd reads the "
                                 "acting object's own position, or the ego's next to a standing object")


def brake(action: SpeedChange, actor: Actor) -> dict[str, float]:
    """The brake profile keys of a speed action."""
    _linear(action.dynamics)
    v0, v1 = actor.speed_mps, action.target_mps
    if actor.direction != 1 or not 0.0 <= v1 < v0:
        raise unsupported(action.elem, f"a speed change from {v0:g} to {v1:g} m/s: crd's objects brake to a lower "
                                       "speed along the ego's heading")
    dyn = action.dynamics
    per_dimension = {"rate": dyn.value, "time": (v0 - v1) / dyn.value, "distance": (v0 * v0 - v1 * v1) / (2 * dyn.value)}
    return {"brake_decel_mps2": per_dimension[dyn.dimension], "brake_to_speed_mps": v1}


def _target_t(action: LaneChange, road: Road, actors: Mapping[str, Actor]) -> float:
    """The target lane's centre offset ``t`` plus ``targetLaneOffset`` (relative lanes skip lane 0)."""
    lane = action.lane
    if lane is None:
        ref = actors.get(action.entity)
        if ref is None:
            raise fail(action.elem, f"entityRef {action.entity!r}: expected an object of this scenario")
        lane = road.lane_at(road.offset_of(ref.pose.x_m, ref.pose.y_m))
        if lane is None:
            raise fail(action.elem, f"{action.entity!r} starts off the lanes of road {road.road_id!r}")
        step = 1 if action.relative > 0 else -1
        for _ in range(abs(action.relative)):
            lane += step
            lane += step if lane == 0 else 0
    if lane not in road.lane_centre_t_m:
        raise fail(action.elem, f"target lane {lane} is not on road {road.road_id!r}")
    return road.lane_centre_t_m[lane] + action.offset_m


def lateral(action: LaneChange, actor: Actor, roads: Mapping[str, Road], actors: Mapping[str, Actor]) -> dict:
    """The lateral profile keys of a lane change."""
    _linear(action.dynamics)
    if len(roads) != 1:
        raise unsupported(action.elem, f"a lane change on a network of {len(roads)} roads: crd reads one road")
    road = next(iter(roads.values()))
    if not road.straight:
        raise unsupported(action.elem, "a lane change on a curved road: crd's 1-D objects move across the ego's "
                                       "start heading")
    if actor.frame.direction(road.hdg_rad, action.elem) != 1:
        raise unsupported(action.elem, "a lane change with the ego against the road's reference line")
    x, y = road.point(0.0, _target_t(action, road, actors))
    end = actor.frame.across(x, y) + actor.direction * actor.body.centre_y_m - actor.frame.ego.centre_y_m
    delta, dyn = abs(end - actor.lateral_m), action.dynamics
    if dyn.dimension == "distance" and actor.speed_mps == 0.0:
        raise unsupported(dyn.elem, "a lane change over a distance by a standing object")
    per_dimension = {"rate": lambda: dyn.value, "time": lambda: delta / dyn.value,
                     "distance": lambda: delta * abs(actor.speed_mps) / dyn.value}
    return {"lateral_end_m": end, "lateral_speed_mps": per_dimension[dyn.dimension]()}
