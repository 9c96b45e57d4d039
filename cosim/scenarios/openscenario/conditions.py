"""Start and stop triggers crd reads: one condition each, as a small record.

A trigger is one ``<ConditionGroup>`` holding one ``<Condition>`` (crd starts
each profile on one event; and/or combinations are not supported yet), with
``conditionEdge`` rising or none. Conditions:

* ``<SimulationTimeCondition rule=greaterThan|greaterOrEqual value>`` (+ the condition's ``delay``);
* ``<RelativeDistanceCondition>`` (longitudinal, rule lessThan|lessOrEqual, ``freespace``);
* ``<TimeToCollisionCondition>`` to an entity or a position (rule lessThan|lessOrEqual, ``freespace``);
* ``<ReachPositionCondition>`` (a :mod:`.positions` position; ``tolerance`` read, no effect);
* ``<TraveledDistanceCondition value>`` (an object's speed change along its trajectory, :mod:`.speed_segments`).

A distance, TTC or position condition needs ``delay = 0`` (crd's gap triggers fire at once).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from .opendrive import Road
from .positions import Pose, read_position
from .xml_source import Element, attr, child, choice, dispatch, fail, number, one_child, only, unsupported

FALLING = ("lessThan", "lessOrEqual")
RISING = ("greaterThan", "greaterOrEqual")


@dataclass(frozen=True)
class AtTime:
    t_s: float
    elem: Element


@dataclass(frozen=True)
class AtDistance:
    """``entity``'s longitudinal distance to ``other`` falls to ``value_m`` (bumper to bumper if ``freespace``)."""

    entity: str
    other: str
    value_m: float
    freespace: bool
    elem: Element


@dataclass(frozen=True)
class AtTtc:
    entity: str
    other: str
    ttc_s: float
    freespace: bool
    elem: Element


@dataclass(frozen=True)
class AtTtcPoint:
    """``entity``'s time to reach a point (its distance along its heading over its speed) falls to ``ttc_s``."""

    entity: str
    pose: Pose
    ttc_s: float
    freespace: bool
    elem: Element


@dataclass(frozen=True)
class AtPosition:
    entity: str
    pose: Pose
    elem: Element


@dataclass(frozen=True)
class AtTravel:
    """``entity`` has travelled ``distance_m`` since the simulation's start."""

    entity: str
    distance_m: float
    elem: Element


def _bool(elem: Element, name: str) -> bool:
    return choice(elem, name, ("true", "false", "1", "0")) in ("true", "1")


def _longitudinal(elem: Element) -> None:
    kind = elem.get("relativeDistanceType", elem.get("type", "longitudinal"))
    if kind != "longitudinal":
        raise unsupported(elem, f"relativeDistanceType={kind!r}: crd's gap is longitudinal")
    choice(elem, "coordinateSystem", ("entity", "road", "lane"), "entity")


def _relative_distance(elem: Element, entity: str, roads: Mapping[str, Road]) -> AtDistance:  # noqa: ARG001
    only(elem, ())
    _longitudinal(elem)
    choice(elem, "rule", FALLING)
    return AtDistance(entity, attr(elem, "entityRef"), number(elem, "value"), _bool(elem, "freespace"), elem)


def _ttc(elem: Element, entity: str, roads: Mapping[str, Road]) -> AtTtc | AtTtcPoint:
    only(elem, ("TimeToCollisionConditionTarget",))
    if elem.get("alongRoute") not in (None, "false", "0"):
        raise unsupported(elem, "alongRoute=true")
    _longitudinal(elem)
    choice(elem, "rule", FALLING)
    target = one_child(child(elem, "TimeToCollisionConditionTarget"), ("EntityRef", "Position"))
    value, freespace = number(elem, "value"), _bool(elem, "freespace")
    if target.tag == "Position":
        return AtTtcPoint(entity, read_position(target, roads), value, freespace, elem)
    return AtTtc(entity, attr(target, "entityRef"), value, freespace, elem)


def _reach(elem: Element, entity: str, roads: Mapping[str, Road]) -> AtPosition:
    only(elem, ("Position",))
    number(elem, "tolerance")
    return AtPosition(entity, read_position(child(elem, "Position"), roads), elem)


def _traveled(elem: Element, entity: str, roads: Mapping[str, Road]) -> AtTravel:  # noqa: ARG001
    only(elem, ())
    distance = number(elem, "value")
    if distance < 0.0:
        raise fail(elem, f"value: expected >= 0, got {distance:g}")
    return AtTravel(entity, distance, elem)


ENTITY_CONDITIONS = {"RelativeDistanceCondition": _relative_distance, "TimeToCollisionCondition": _ttc,
                     "ReachPositionCondition": _reach, "TraveledDistanceCondition": _traveled}


def _by_entity(elem: Element, delay_s: float, roads: Mapping[str, Road]) -> AtDistance | AtTtc | AtTtcPoint | AtPosition \
        | AtTravel:
    only(elem, ("TriggeringEntities", "EntityCondition"))
    triggering = child(elem, "TriggeringEntities")
    refs = only(triggering, ("EntityRef",))
    if len(refs) != 1:
        raise unsupported(triggering, f"{len(refs)} triggering entities: crd reads one")
    if delay_s != 0.0:
        raise unsupported(elem, f"delay={delay_s}: crd's distance triggers fire at once")
    return dispatch(one_child(child(elem, "EntityCondition")), ENTITY_CONDITIONS, attr(refs[0], "entityRef"), roads)


def _by_value(elem: Element, delay_s: float, roads: Mapping[str, Road]) -> AtTime:  # noqa: ARG001
    cond = one_child(elem)
    if cond.tag != "SimulationTimeCondition":
        raise unsupported(cond)
    only(cond, ())
    choice(cond, "rule", RISING)
    return AtTime(number(cond, "value") + delay_s, cond)


CONDITION_KINDS = {"ByValueCondition": _by_value, "ByEntityCondition": _by_entity}


def read_trigger(elem: Element | None, roads: Mapping[str, Road]) -> AtTime | AtDistance | AtTtc | AtPosition | None:
    """A ``<StartTrigger>``/``<StopTrigger>``: its one condition, or None for an empty trigger."""
    if elem is None:
        return None
    groups = only(elem, ("ConditionGroup",))
    if not groups:
        return None
    if len(groups) != 1:
        raise unsupported(groups[1], "several condition groups (or): crd starts on one condition")
    conditions = only(groups[0], ("Condition",))
    if len(conditions) != 1:
        raise unsupported(groups[0], f"{len(conditions)} conditions (and): crd starts on one condition")
    cond = conditions[0]
    choice(cond, "conditionEdge", ("rising", "none"))
    attr(cond, "name")
    delay_s = number(cond, "delay", 0.0)
    if delay_s < 0.0:
        raise fail(cond, f"delay: expected >= 0, got {delay_s}")
    return dispatch(one_child(cond), CONDITION_KINDS, delay_s, roads)
