"""An OpenSCENARIO 1.x file (with its OpenDRIVE road) as a crd :class:`~cosim.scenarios.config.Scenario`.

The file is read strictly (:mod:`.xml_source`): what crd's world can follow maps onto the scenario
keys (docs/openscenario.md): objects on the ego's axis as the 1-D keys and profiles
(:mod:`.profiles`); a curved road, or a straight one under a steering ego, as the planar ``[road]``
(:mod:`.planar_road`); objects on that road, across the ego or placed relative to an entity as
``road_pose``/``pose`` (:mod:`.placement`); trajectories and crossings (:mod:`.trajectory_keys`).
Anything else is a one-line error naming the file, the line and the element. The mapped keys go through the same
loader as a TOML file (:func:`cosim.scenarios.loader.scenario_from_dict`), so ranges and cross-key
rules hold the same; a loader error names the property or element it came from.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

from ...errors import ConfigError
from ..config import Scenario
from ..loader import scenario_from_dict
from .actions import LaneChange, SpeedChange, Teleport
from .conditions import AtTravel
from .entities import Body, read_entities
from .frame import Frame
from .opendrive import Road, read_opendrive
from .planar_road import ego_lane, road_keys
from .properties import nested
from .profiles import Actor, brake, lateral, trigger
from .story import Storyboard, read_storyboard
from .placement import placement_keys
from .trajectory import FollowTrajectory
from .trajectory_keys import Motion, trajectory_keys
from .xml_source import Element, XmlScenarioError, attr, child, children, fail, number, only, parse_file, unsupported

EGO_NAMES = ("ego", "hero")
TOP = ("FileHeader", "ParameterDeclarations", "CatalogLocations", "RoadNetwork", "Entities", "Storyboard")
#: the sections crd reads from the ego's crd.* properties ([driver] comes from its controller)
EGO_SECTIONS = ("scenario", "plant", "radar", "gateway", "ecu", "checks", "end")
#: the ego's property that keeps one object as ``[[objects]]`` (a table form, so a round trip writes the same TOML)
OBJECTS_TABLE = "objects_table"


def pick_ego(bodies: Mapping[str, Body], wanted: str | None, root: Element) -> Body:
    """The ego: ``wanted`` by name, else the one entity named ``Ego``/``hero`` (any case)."""
    if wanted is not None:
        if wanted not in bodies:
            raise fail(root, f"--ego {wanted!r}: no such entity (entities: {', '.join(bodies)})")
        return bodies[wanted]
    named = [b for n, b in bodies.items() if n.lower() in EGO_NAMES]
    if len(named) != 1:
        raise fail(root, f"cannot tell the ego among {', '.join(bodies)}: name it Ego or hero, or give --ego NAME")
    return named[0]


def _roads(root: Element, base: Path) -> dict[str, Road]:
    network = child(root, "RoadNetwork", False)
    if network is None:
        return {}
    only(network, ("LogicFile", "SceneGraphFile"))
    logic = child(network, "LogicFile", False)
    return {} if logic is None else read_opendrive(base / attr(logic, "filepath"))


def _header(root: Element) -> str:
    head = child(root, "FileHeader")
    if number(head, "revMajor") != 1 or number(head, "revMinor") not in (0, 1, 2, 3):
        raise unsupported(head, f"OpenSCENARIO {head.get('revMajor')}.{head.get('revMinor')}: crd reads 1.0 to 1.3")
    for tag in ("ParameterDeclarations", "CatalogLocations"):
        if (c := child(root, tag, False)) is not None and children(c):
            raise unsupported(children(c)[0], "crd reads self-contained files without parameters or catalogues")
    return head.get("description", "")


def _start(body: Body, init: list, follows: bool = False) -> tuple[Teleport, float]:
    """The entity's Init teleport and absolute speed (step); an object's trajectory may be there too."""
    where = body.elem
    teleports = [a for a in init if isinstance(a, Teleport)]
    speeds = [a for a in init if isinstance(a, SpeedChange)]
    if len(teleports) != 1:
        raise fail(where, f"entity {body.name!r}: expected one TeleportAction in Init, got {len(teleports)}")
    kinds = (Teleport, SpeedChange, FollowTrajectory) if follows else (Teleport, SpeedChange)
    if len([a for a in init if isinstance(a, FollowTrajectory)]) > 1:
        raise unsupported(init[-1].elem, "in Init: crd reads one trajectory per object")
    for a in init:
        if not isinstance(a, kinds) or len(speeds) > 1:
            raise unsupported(a.elem, "in Init: crd reads one teleport and one speed per entity (and an object's "
                                      "trajectory)")
    if speeds and speeds[0].dynamics.shape != "step":
        raise unsupported(speeds[0].dynamics.elem, "a speed transition in Init: entities start at their speed (step)")
    return teleports[0], speeds[0].target_mps if speeds else 0.0


class _Build:
    """The state of one file's mapping (keeps signatures short)."""

    def __init__(self, path: Path, ego_name: str | None) -> None:
        self.path = path
        self.root = parse_file(path, "OpenSCENARIO")
        only(self.root, TOP)
        self.name = _header(self.root) or path.stem
        self.roads = _roads(self.root, path.parent)
        self.bodies = read_entities(child(self.root, "Entities"))
        self.ego = pick_ego(self.bodies, ego_name, self.root)
        self.board: Storyboard = read_storyboard(child(self.root, "Storyboard"), self.roads)
        self.origins: dict[str, Element] = {}
        self.plane_road: Road | None = None  #: the file's road when it is the scenario's [road]

    def actors(self, frame: Frame, ego_speed: float) -> dict[str, Actor]:
        out = {}
        for name, body in self.bodies.items():
            if body is self.ego:
                continue
            teleport, speed = _start(body, self.board.init.get(name, []), follows=True)
            direction = frame.aligned(teleport.pose.h_rad) or 1  # across the ego: placed in the plane
            out[name] = Actor(body, teleport.pose, direction, direction * speed, frame, ego_speed)
        unknown = set(self.board.init) - set(self.bodies)
        if unknown:
            raise fail(self.root, f"Init names unknown entities {sorted(unknown)}")
        return out

    def object_keys(self, actor: Actor, actors: Mapping[str, Actor]) -> dict[str, Any]:
        name = actor.body.name
        keys: dict[str, Any] = {"name": name, "length_m": actor.body.length_m, "width_m": actor.body.width_m}
        events = [e for e in self.board.events if e.actor == name]
        motion = self._motion(actor, events)
        if motion is not None:
            keys |= trajectory_keys(motion, actor.pose, actor.frame, self.plane_road, self.ego.name)
        elif self._in_plane(actor):
            if events:
                raise unsupported(events[0].action.elem, f"a story action of {name!r}, placed in the plane: crd "
                                                         "reads these for objects on the ego's axis")
            keys |= placement_keys(actor.body, actor.pose, actor.frame, self.plane_road)
            keys["speed_mps"] = abs(actor.speed_mps)
        else:
            keys |= {"position_m": actor.rear_m, "speed_mps": actor.speed_mps, "lateral_m": actor.lateral_m}
            done: set[str] = set()
            for event in events:
                self._event_keys(event, actor, actors, keys, done)
        for key, value in nested(actor.body.properties).items():
            if key in keys:
                prop = actor.body.properties[f"crd.{key}"][1]
                raise fail(prop, f"property crd.{key}: already given by the standard elements")
            keys[key] = value
        return keys

    def _in_plane(self, actor: Actor) -> bool:
        """Across the ego's axis, placed relative to an entity, or on the road that is the scenario's ``[road]``."""
        spot, road = actor.pose.spot, self.plane_road
        on_road = spot is not None and road is not None and spot.road_id == road.road_id
        return on_road or actor.pose.relative is not None or actor.frame.aligned(actor.pose.h_rad) is None

    def _motion(self, actor: Actor, events: list) -> Motion | None:
        """The object's trajectory, its start and a speed change of the same event (None: no trajectory)."""
        name = actor.body.name
        in_init = [a for a in self.board.init.get(name, []) if isinstance(a, FollowTrajectory)]
        story = [e for e in events if isinstance(e.action, FollowTrajectory)]
        if not in_init and not story:
            return None
        if len(in_init) + len(story) > 1:
            raise unsupported(story[-1].action.elem, f"a second trajectory for {name!r}: crd's objects follow one")
        start = story[0].start if story else None
        rest = [e for e in events if not isinstance(e.action, FollowTrajectory)]
        speed = [e for e in rest if isinstance(e.action, SpeedChange) and story and e.start is start]
        later = [e for e in rest if isinstance(e.action, SpeedChange) and isinstance(e.start, AtTravel)
                 and e.start.entity == name and e.start is not start]
        if len(rest) != len(speed) + len(later) or len(speed) > 1:
            raise unsupported(rest[-1].action.elem, f"{type(rest[-1].action).__name__} for {name!r}, which follows "
                                                    "a trajectory: crd reads one speed action in the same event, and "
                                                    "speed actions started by its own TraveledDistanceCondition")
        follow = in_init[0] if in_init else story[0].action
        _, speed0 = _start(actor.body, self.board.init.get(name, []), follows=True)
        return Motion(follow, start, speed[0].action if speed else None, actor.body, speed0, actor.pose.h_rad,
                      tuple((e.start.distance_m, e.action) for e in later))

    def _event_keys(self, event, actor: Actor, actors: Mapping[str, Actor], keys: dict, done: set) -> None:
        action = event.action
        kind = {SpeedChange: "brake", LaneChange: "lateral"}.get(type(action))
        if kind is None:
            raise unsupported(action.elem, "in the story: crd's objects start where Init puts them")
        if kind in done:
            raise unsupported(action.elem, f"a second {type(action).__name__} for {actor.body.name!r}: crd's objects "
                                           f"have one {kind} profile")
        done.add(kind)
        keys.update(brake(action, actor) if kind == "brake" else lateral(action, actor, self.roads, actors))
        at, value = trigger(event.start, actor, self.ego.name)
        keys[f"{kind}_{at}"] = value

    def scenario_dict(self) -> dict[str, Any]:
        ego_start, ego_speed = _start(self.ego, self.board.init.get(self.ego.name, []))
        for event in self.board.events:
            if event.actor == self.ego.name:
                raise unsupported(event.action.elem, "an action of the ego in the story: crd's driver models drive "
                                                     "the ego (its <Controller name=\"crd_driver\">)")
            if event.actor not in self.bodies:
                raise fail(event.action.elem, f"actor {event.actor!r} is not an entity")
        frame = Frame(self.ego, ego_start.pose)
        actors = self.actors(frame, ego_speed)
        data = nested(self.ego.properties, origins=self.origins)
        table = data.pop(OBJECTS_TABLE, "object")
        if table not in ("object", "objects"):
            raise fail(self.origins[OBJECTS_TABLE], f"property crd.{OBJECTS_TABLE}: expected \"object\" or "
                                                    f"\"objects\", got {table!r}")
        for section in data:
            if section not in EGO_SECTIONS:
                origin = self.origins[next(p for p in self.origins if p.split(".")[0] == section)]
                raise fail(origin, f"property crd.{section}.*: expected a section of {', '.join(EGO_SECTIONS)}")
        self._ego_keys(data, ego_speed)
        self._road_keys(data, frame, ego_start)
        objs = [self.object_keys(a, actors) for a in actors.values()]
        if len(objs) == 1 and table == "object":
            data["object"] = objs[0]
        elif objs:
            data["objects"] = objs
        else:
            data["object"] = {"enabled": False}
        return data

    def _ego_keys(self, data: dict[str, Any], speed: float) -> None:
        scenario = data.setdefault("scenario", {})
        scenario.setdefault("name", self.name)
        if self.board.stop is not None:
            scenario["duration_s"] = self.board.stop.t_s
        plant = data.setdefault("plant", {})
        plant.update(initial_speed_mps=speed, length_m=self.ego.length_m, width_m=self.ego.width_m)
        driver = {"model": "hold_speed", "set_speed_mps": speed}
        if self.ego.driver is not None:
            driver = nested(self.ego.driver, prefix="", origins=self.origins)
        data["driver"] = driver


    def _road_keys(self, data: dict[str, Any], frame: Frame, ego_start: Teleport) -> None:
        """A curved road, or a steering ego, makes the road the scenario's ``[road]`` (and the ego keeps its lane)."""
        if all(r.straight for r in self.roads.values()) and "steering" not in data["driver"]:
            return
        where = child(child(self.root, "RoadNetwork"), "LogicFile")
        if len(self.roads) != 1:
            raise unsupported(where, f"a curved road or a steering ego in a network of {len(self.roads)} roads: "
                                     "crd's [road] is one")
        road = next(iter(self.roads.values()))
        data["road"] = road_keys(road, frame, where)
        self.plane_road = road
        if "steering" not in data["driver"]:
            lane = ego_lane(road, ego_start.pose, ego_start.elem)
            data["driver"]["steering"] = {"model": "path_following", "lane": lane}


def _located(exc: ConfigError, build: _Build) -> XmlScenarioError:
    """A loader error, named by the property it came from when there is one."""
    text = str(exc)
    path = text.split(":", 1)[0]
    for key in (path, path.split(".", 1)[-1]):
        if key in build.origins:
            return fail(build.origins[key], text)
    return XmlScenarioError(f"{build.path}: {text}")


def xosc_to_dict(path: str | Path, ego: str | None = None) -> dict[str, Any]:
    """The keys an OpenSCENARIO file gives, as a partial scenario mapping (not yet checked by the loader)."""
    return _Build(Path(path), ego).scenario_dict()


def read_xosc(path: str | Path, ego: str | None = None) -> Scenario:
    """Read an OpenSCENARIO file as a scenario; ``ego`` names the equipped car (default Ego/hero)."""
    build = _Build(Path(path), ego)
    data = build.scenario_dict()
    try:
        return scenario_from_dict(data, base_dir=build.path.parent)
    except XmlScenarioError:
        raise
    except ConfigError as exc:
        raise _located(exc, build) from None
