"""Strict reading of OpenSCENARIO and OpenDRIVE XML: every error names the file, the line and the element.

Both readers walk the tree through tables from element name to handler; an
element that no table names is :func:`unsupported` (one line: file, line,
element), never skipped. Numbers are read by :func:`number`, which refuses
parameter references (``$name``) and expressions: crd reads concrete files.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable, Iterable, Mapping

from lxml import etree

from ...errors import ConfigError

Element = etree._Element


class XmlScenarioError(ConfigError):
    """A file outside crd's OpenSCENARIO/OpenDRIVE subset or with a bad value: ``file:line: <Element>: problem``."""


def where(elem: Element) -> str:
    """``file:line: <Tag>`` of an element (the file is the parsed document's URL)."""
    return f"{elem.getroottree().docinfo.URL}:{elem.sourceline}: <{elem.tag}>"


def fail(elem: Element, problem: str) -> XmlScenarioError:
    """An error at ``elem``, to raise."""
    return XmlScenarioError(f"{where(elem)}: {problem}")


def unsupported(elem: Element, why: str = "") -> XmlScenarioError:
    """``not supported yet: <Tag> at line N`` (why) with the file, to raise."""
    url = elem.getroottree().docinfo.URL
    return XmlScenarioError(f"{url}: not supported yet: <{elem.tag}> at line {elem.sourceline}"
                            + (f" ({why})" if why else ""))


def parse_file(path: Path, root_tag: str) -> Element:
    """The root element of an XML file, which must be ``root_tag``."""
    try:
        tree = etree.parse(str(path), etree.XMLParser(remove_comments=True, resolve_entities=False))
    except OSError:
        raise ConfigError(f"{path}: file not found or unreadable") from None
    except etree.XMLSyntaxError as exc:
        raise ConfigError(f"{path}: invalid XML: {exc}") from None
    root = tree.getroot()
    if root.tag != root_tag:
        raise fail(root, f"expected the root element <{root_tag}>")
    return root


def children(elem: Element) -> list[Element]:
    """The element children (comments and processing instructions left out)."""
    return [c for c in elem if isinstance(c.tag, str)]


def attr(elem: Element, name: str, default: str | None = None) -> str:
    """A text attribute; missing without a default is an error."""
    value = elem.get(name, default)
    if value is None:
        raise fail(elem, f"missing attribute {name!r}")
    if value.startswith("$"):
        raise unsupported(elem, f"parameter reference {name}={value!r}: crd reads concrete values")
    return value


def number(elem: Element, name: str, default: float | None = None) -> float:
    """A finite number attribute."""
    text = attr(elem, name, None if default is None else repr(default))
    try:
        value = float(text)
    except ValueError:
        raise fail(elem, f"attribute {name}: expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise fail(elem, f"attribute {name}: expected a finite number, got {text!r}")
    return value


def choice(elem: Element, name: str, allowed: Iterable[str], default: str | None = None) -> str:
    """A text attribute from ``allowed``; another value is not supported yet."""
    value = attr(elem, name, default)
    allowed = tuple(allowed)
    if value not in allowed:
        raise unsupported(elem, f"{name}={value!r}; crd reads {', '.join(repr(a) for a in allowed)}")
    return value


def one_child(elem: Element, allowed: Iterable[str] | None = None) -> Element:
    """The single element child of ``elem`` (from ``allowed`` when given)."""
    kids = children(elem)
    if len(kids) != 1:
        raise fail(elem, f"expected one child element, got {len(kids)}")
    if allowed is not None and kids[0].tag not in tuple(allowed):
        raise unsupported(kids[0])
    return kids[0]


def child(elem: Element, tag: str, required: bool = True) -> Element | None:
    """The child ``tag`` (at most one)."""
    found = [c for c in children(elem) if c.tag == tag]
    if len(found) > 1:
        raise fail(found[1], f"expected at most one <{tag}> in <{elem.tag}>")
    if required and not found:
        raise fail(elem, f"missing child <{tag}>")
    return found[0] if found else None


def only(elem: Element, allowed: Iterable[str]) -> list[Element]:
    """The children of ``elem``; one whose tag is not in ``allowed`` is not supported yet."""
    allowed = frozenset(allowed)
    kids = children(elem)
    for kid in kids:
        if kid.tag not in allowed:
            raise unsupported(kid, f"inside <{elem.tag}>")
    return kids


def dispatch(elem: Element, table: Mapping[str, Callable], *args):
    """``table[elem.tag](elem, *args)``; a tag the table lacks is not supported yet."""
    handler = table.get(elem.tag)
    if handler is None:
        raise unsupported(elem)
    return handler(elem, *args)
