"""``<Entities>``: each ``<ScenarioObject>`` as a :class:`Body` (box, category, crd properties, driver).

Read: ``<Vehicle>`` (any ``vehicleCategory``: car, bicycle, ...) and
``<Pedestrian>`` with their ``<BoundingBox>``; ``<Performance>``, ``<Axles>``
and a pedestrian's mass are read and have no effect (the plant FMU defines the
ego's dynamics, the objects follow their profiles). ``<Properties>`` named
``crd.*`` carry crd's own keys (:mod:`.properties`); other names belong to
other tools and are left to them. An ``<ObjectController>`` may hold one
``<Controller name="crd_driver">`` whose properties are crd's ``[driver]`` keys.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .xml_source import Element, attr, child, children, dispatch, fail, number, only, unsupported

DRIVER_CONTROLLER = "crd_driver"


@dataclass(frozen=True)
class Body:
    """One entity: its box relative to its reference point, and what crd reads from its properties."""

    name: str
    category: str
    length_m: float
    width_m: float
    centre_x_m: float  #: box centre ahead of the reference point
    centre_y_m: float  #: box centre left of the reference point
    properties: dict[str, tuple[str, Element]] = field(default_factory=dict)
    driver: dict[str, tuple[str, Element]] | None = None
    elem: Element | None = None

    @property
    def front_m(self) -> float:
        """The front bumper ahead of the reference point."""
        return self.centre_x_m + self.length_m / 2

    @property
    def rear_m(self) -> float:
        """The rear ahead of the reference point (negative: behind it)."""
        return self.centre_x_m - self.length_m / 2


def properties(elem: Element | None) -> dict[str, tuple[str, Element]]:
    """``<Properties>``: name -> (value text, element); ``<File>`` entries are not supported."""
    if elem is None:
        return {}
    out = {}
    for prop in only(elem, ("Property",)):
        name = attr(prop, "name")
        if name in out:
            raise fail(prop, f"property {name!r} given twice")
        out[name] = (attr(prop, "value"), prop)
    return out


def _box(owner: Element) -> tuple[float, float, float, float]:
    box = child(owner, "BoundingBox")
    only(box, ("Center", "Dimensions"))
    centre, dims = child(box, "Center"), child(box, "Dimensions")
    return number(dims, "length"), number(dims, "width"), number(centre, "x"), number(centre, "y")


def _vehicle(elem: Element) -> tuple[str, tuple, dict]:
    only(elem, ("ParameterDeclarations", "BoundingBox", "Performance", "Axles", "Properties", "TrailerHitch",
                "TrailerCoupler", "Trailer"))
    for tag in ("ParameterDeclarations", "TrailerHitch", "TrailerCoupler", "Trailer"):
        if (c := child(elem, tag, False)) is not None and (tag != "ParameterDeclarations" or children(c)):
            raise unsupported(c)
    return attr(elem, "vehicleCategory"), _box(elem), properties(child(elem, "Properties", False))


def _pedestrian(elem: Element) -> tuple[str, tuple, dict]:
    only(elem, ("ParameterDeclarations", "BoundingBox", "Properties"))
    if (c := child(elem, "ParameterDeclarations", False)) is not None and children(c):
        raise unsupported(c)
    return "pedestrian", _box(elem), properties(child(elem, "Properties", False))


def _catalog_reference(elem: Element) -> tuple:
    raise unsupported(elem, "catalogues: give the entity inline")


ENTITY_KINDS = {"Vehicle": _vehicle, "Pedestrian": _pedestrian, "CatalogReference": _catalog_reference}


def _driver(elem: Element | None) -> dict[str, tuple[str, Element]] | None:
    if elem is None:
        return None
    ctrl = only(elem, ("Controller", "CatalogReference"))
    if len(ctrl) != 1 or ctrl[0].tag != "Controller":
        raise unsupported(ctrl[0] if ctrl else elem, "crd reads one inline <Controller>")
    if attr(ctrl[0], "name") != DRIVER_CONTROLLER:
        raise unsupported(ctrl[0], f"controller {ctrl[0].get('name')!r}: crd drives the ego with its driver models,"
                                   f" <Controller name=\"{DRIVER_CONTROLLER}\"> with [driver] keys as properties")
    only(ctrl[0], ("ParameterDeclarations", "Properties"))
    return properties(child(ctrl[0], "Properties", False))


def _scenario_object(elem: Element) -> Body:
    kids = only(elem, ("Vehicle", "Pedestrian", "CatalogReference", "ObjectController"))
    kinds = [k for k in kids if k.tag != "ObjectController"]
    if len(kinds) != 1:
        raise fail(elem, "expected one entity definition (<Vehicle> or <Pedestrian>)")
    category, (length, width, cx, cy), props = dispatch(kinds[0], ENTITY_KINDS)
    driver = _driver(child(elem, "ObjectController", False))
    return Body(attr(elem, "name"), category, length, width, cx, cy, props, driver, elem)


def read_entities(elem: Element) -> dict[str, Body]:
    """Every ``<ScenarioObject>`` by name (``<EntitySelection>`` is not supported)."""
    bodies: dict[str, Body] = {}
    for obj in only(elem, ("ScenarioObject",)):
        body = _scenario_object(obj)
        if body.name in bodies:
            raise fail(obj, f"entity {body.name!r} defined twice")
        bodies[body.name] = body
    return bodies
