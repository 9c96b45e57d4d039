"""``<Storyboard>``: the Init actions per entity, the story's events, and the stop trigger.

Init: ``<Private entityRef>`` with teleport and speed actions (global actions
are not supported yet); a teleport relative to an entity is placed from that entity's own Init
teleport, which must be absolute. Story: ``<Story>`` / ``<Act>`` (started at simulation
time 0, no stop trigger) / ``<ManeuverGroup maximumExecutionCount="1">`` with
``<Actors>`` by ``<EntityRef>`` / ``<Maneuver>`` / ``<Event>`` (executed once)
with private ``<Action>`` elements and one start condition (:mod:`.conditions`);
each action applies to every actor of its group.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Mapping

from .actions import LaneChange, SpeedChange, Teleport, read_action, read_private_action
from .conditions import AtDistance, AtPosition, AtTime, AtTravel, AtTtc, AtTtcPoint, read_trigger
from .opendrive import Road
from .positions import resolve
from .xml_source import Element, attr, child, children, fail, number, only, unsupported

Condition = AtTime | AtDistance | AtTtc | AtTtcPoint | AtPosition | AtTravel


@dataclass(frozen=True)
class StoryEvent:
    """One action of one actor, started by one condition."""

    actor: str
    action: SpeedChange | LaneChange | Teleport
    start: Condition


@dataclass(frozen=True)
class Storyboard:
    init: dict[str, list[Teleport | SpeedChange | LaneChange]] = field(default_factory=dict)
    events: list[StoryEvent] = field(default_factory=list)
    stop: Condition | None = None


def _no_parameters(elem: Element) -> None:
    params = child(elem, "ParameterDeclarations", False)
    if params is not None and children(params):
        raise unsupported(params, "parameters: crd reads concrete values")


def _init(elem: Element, roads: Mapping[str, Road]) -> dict[str, list]:
    actions = child(elem, "Actions")
    only(elem, ("Actions",))
    out: dict[str, list] = {}
    for private in only(actions, ("Private",)):
        entity = attr(private, "entityRef")
        out.setdefault(entity, []).extend(read_private_action(a, roads) for a in only(private, ("PrivateAction",)))
    return out


def _placed(init: dict[str, list]) -> dict[str, list]:
    """``init`` with each relative teleport placed from its entity's absolute Init teleport."""
    placed = {name: next((a.pose for a in actions if isinstance(a, Teleport)), None) for name, actions in init.items()}
    out = {}
    for name, actions in init.items():
        out[name] = [_resolved(a, placed) if isinstance(a, Teleport) and a.pose.relative is not None else a
                     for a in actions]
    return out


def _resolved(teleport: Teleport, placed: dict) -> Teleport:
    rel = teleport.pose.relative
    anchor = placed.get(rel.entity)
    if anchor is None or anchor.relative is not None:
        raise unsupported(rel.elem, f"a position relative to {rel.entity!r}, which Init does not place by an "
                                    "absolute position")
    return dataclasses.replace(teleport, pose=resolve(teleport.pose, anchor))


def _executed_once(elem: Element) -> None:
    if number(elem, "maximumExecutionCount", 1.0) != 1.0:
        raise unsupported(elem, f"maximumExecutionCount={elem.get('maximumExecutionCount')}: crd runs each once")


def _event(elem: Element, actors: list[str], roads: Mapping[str, Road]) -> list[StoryEvent]:
    _executed_once(elem)
    only(elem, ("Action", "StartTrigger"))
    start = read_trigger(child(elem, "StartTrigger"), roads)
    if start is None:
        raise fail(elem, "expected a start condition")
    actions = [read_action(a, roads) for a in children(elem) if a.tag == "Action"]
    return [StoryEvent(actor, action, start) for action in actions for actor in actors]


def _maneuver_group(elem: Element, roads: Mapping[str, Road]) -> list[StoryEvent]:
    _executed_once(elem)
    only(elem, ("Actors", "Maneuver", "CatalogReference"))
    actors_elem = child(elem, "Actors")
    actors = [attr(r, "entityRef") for r in only(actors_elem, ("EntityRef",))]
    if actors_elem.get("selectTriggeringEntities") in ("true", "1"):
        raise unsupported(actors_elem, "selectTriggeringEntities=true: name the actors")
    events = []
    for maneuver in (m for m in children(elem) if m.tag != "Actors"):
        if maneuver.tag == "CatalogReference":
            raise unsupported(maneuver, "catalogues: give the maneuver inline")
        _no_parameters(maneuver)
        only(maneuver, ("ParameterDeclarations", "Event"))
        for event in (e for e in children(maneuver) if e.tag == "Event"):
            events.extend(_event(event, actors, roads))
    return events


def _act(elem: Element, roads: Mapping[str, Road]) -> list[StoryEvent]:
    only(elem, ("ManeuverGroup", "StartTrigger", "StopTrigger"))
    start = read_trigger(child(elem, "StartTrigger", False), roads)
    if start is not None and not (isinstance(start, AtTime) and start.t_s == 0.0):
        raise unsupported(start.elem, "an act that starts later than time 0: put the condition on its events")
    if read_trigger(child(elem, "StopTrigger", False), roads) is not None:
        raise unsupported(child(elem, "StopTrigger"), "an act's stop trigger")
    return [e for g in children(elem) if g.tag == "ManeuverGroup" for e in _maneuver_group(g, roads)]


def read_storyboard(elem: Element, roads: Mapping[str, Road]) -> Storyboard:
    """The whole ``<Storyboard>``."""
    only(elem, ("Init", "Story", "StopTrigger"))
    events = []
    for story in (s for s in children(elem) if s.tag == "Story"):
        _no_parameters(story)
        only(story, ("ParameterDeclarations", "Act"))
        events.extend(e for act in children(story) if act.tag == "Act" for e in _act(act, roads))
    stop = read_trigger(child(elem, "StopTrigger", False), roads)
    if stop is not None and not isinstance(stop, AtTime):
        raise unsupported(stop.elem, "a stop trigger other than simulation time: crd's [end] keys go in the ego's "
                                     "crd.end.* properties")
    return Storyboard(_placed(_init(child(elem, "Init"), roads)), events, stop)
