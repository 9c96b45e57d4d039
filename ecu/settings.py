"""Declared settings: one way to declare a configuration key, one loader, one error format.

Every configuration file of crd (a scenario, its ``[ecu]``, a standalone ECU
file, a test catalogue, a sweep) is read into frozen dataclasses whose fields
declare their keys once, next to the field, with :func:`setting`: type (the
annotation), doc, unit, allowed values (a :class:`Range` or a tuple of
choices), default. :func:`load` builds a dataclass from a TOML table and
checks it against those declarations; reference pages are rendered from them
(:func:`keys`, :func:`walk`; :mod:`cosim.scenarios.reference`).

What :func:`load` does with a field follows from its annotation alone:

* ``float``, ``int``, ``bool``, ``str`` (optionally ``| None``): a scalar of that
  type (a TOML integer is accepted for a float, nothing else is coerced; floats
  must be finite), within the declared :class:`Range` or one of the choices;
* a union of scalar types (``int | float | bool | str``): any one of them;
* a dataclass: a nested table, loaded by the same rules;
* ``tuple[X, ...]``: a list of X (a list of tables for a dataclass X);
* ``Mapping[str, X]``: a free mapping whose names the file chooses (FMU start
  values, source keys, named targets); every value is checked as an X;
* a field declared with a :class:`Kind`: the kind's own ``parse`` (e.g. a table of
  signal maps, a breakpoint table); its ``dump`` writes the value back.

Errors are :class:`SettingError` (a :class:`~ecu.errors.ConfigError`), one line:
``<key.path>: <problem>``, and :func:`load_toml` puts the file in front:
``<file>: <key.path>: <problem>; did you mean <x>?``. A problem gives the
expected and the actual value. A dataclass may refuse a combination of values
by raising ``SettingError`` with a key relative to itself from ``__post_init__``;
the loader puts the table's path in front.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import tomllib
import types
import typing
from collections.abc import Mapping
from dataclasses import MISSING, dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Iterator, TypeVar

from .errors import ConfigError

T = TypeVar("T")
_SCALARS = (bool, int, float, str)


class SettingError(ConfigError):
    """A bad value at a key path: ``<path>: <problem>``; :meth:`under` prefixes the path of the enclosing table."""

    def __init__(self, path: str, problem: str) -> None:
        super().__init__(f"{path}: {problem}" if path else problem)
        self.path, self.problem = path, problem

    def under(self, prefix: str) -> "SettingError":
        return SettingError(join(prefix, self.path), self.problem) if prefix else self


@dataclass(frozen=True)
class Kind:
    """A value that is not a plain scalar, list or table: its own parser, writer and description."""

    name: str  #: what the value is, for the reference (``table of role = FMU variable``)
    parse: Callable[[Any, str], Any]  #: ``parse(toml_value, key_path)`` -> the field's value
    dump: Callable[[Any], Any] = lambda value: value  #: the field's value -> plain TOML data


@dataclass(frozen=True)
class Range:
    """The allowed interval of a number: ``[low, high]``, or ``(low, high]`` with ``low_open``."""

    low: float
    high: float
    low_open: bool = False

    def __contains__(self, value: float) -> bool:
        above = value > self.low if self.low_open else value >= self.low
        return above and value <= self.high and math.isfinite(value)

    def __str__(self) -> str:
        num = lambda x: repr(x) if isinstance(x, int) else f"{x:g}"  # noqa: E731
        return (f"{'(' if self.low_open else '['}{num(self.low)}, {num(self.high)}"
                f"{')' if self.high == math.inf else ']'}")


@dataclass(frozen=True)
class Declared:
    """What :func:`setting` records in a field's metadata."""

    doc: str = ""
    unit: str = ""
    range: Range | None = None
    choices: tuple | None = None
    kind: Kind | None = None


def setting(default: Any = MISSING, *, doc: str = "", unit: str = "", allowed: Range | Iterable | None = None,
            kind: Kind | None = None, factory: Any = MISSING) -> Any:
    """A dataclass field declaring one key: ``allowed`` is a :class:`Range` or the tuple of choices."""
    choices = None if allowed is None or isinstance(allowed, Range) else tuple(allowed)
    declared = Declared(doc, unit, allowed if isinstance(allowed, Range) else None, choices, kind)
    return dataclasses.field(default=default, default_factory=factory, metadata={"setting": declared})


@dataclass(frozen=True)
class Key:
    """One declared key of a dataclass: its field, resolved type and declaration."""

    name: str
    hint: Any
    declared: Declared
    field: dataclasses.Field

    @property
    def required(self) -> bool:
        return self.field.default is MISSING and self.field.default_factory is MISSING

    @property
    def default(self) -> Any:
        if self.field.default is not MISSING:
            return self.field.default
        return None if self.required else self.field.default_factory()


@functools.cache
def keys(cls: type) -> dict[str, Key]:
    """The declared keys of dataclass ``cls`` (every ``init`` field), in declaration order."""
    hints = typing.get_type_hints(cls)
    return {f.name: Key(f.name, hints[f.name], f.metadata.get("setting", Declared()), f)
            for f in dataclasses.fields(cls) if f.init}


def walk(cls: type, prefix: str = "") -> Iterator[tuple[str, Key]]:
    """Every declared key of ``cls`` and of its nested tables, with its key path (lists are not entered)."""
    for key in keys(cls).values():
        path = join(prefix, key.name)
        yield path, key
        if key.declared.kind is None and dataclasses.is_dataclass(_plain(key.hint)):
            yield from walk(_plain(key.hint), path)


def join(prefix: str, key: str) -> str:
    """``a.b`` + ``c`` -> ``a.b.c``; an index (``[2]``) is appended without a dot."""
    if not prefix:
        return key
    return f"{prefix}{key}" if key.startswith("[") else f"{prefix}.{key}"


def near_miss(word: str, candidates: Iterable[str]) -> str | None:
    """The closest candidate to ``word`` (difflib, cutoff 0.6), if any."""
    import difflib  # here: only a bad key needs it (1 ms less at every ECU start)

    close = difflib.get_close_matches(str(word), [str(c) for c in candidates], n=1, cutoff=0.6)
    return close[0] if close else None


def unknown_key(where: str, key: str, valid: Iterable[str]) -> SettingError:
    """``<where.key>: unknown key; did you mean <where.near>?`` (or the valid keys when none is near)."""
    valid = list(valid)
    near = near_miss(key, valid)
    hint = f"did you mean {join(where, near)}?" if near else f"expected one of {', '.join(valid) or 'no keys'}"
    return SettingError(join(where, str(key)), f"unknown key; {hint}")


def check_keys(table: Any, valid: Iterable[str], where: str) -> Mapping[str, Any]:
    """``table`` as a mapping whose keys are all in ``valid``."""
    if not isinstance(table, Mapping):
        raise SettingError(where, f"expected a table, got {table!r}")
    valid = tuple(valid)
    for key in table:
        if key not in valid:
            raise unknown_key(where, key, valid)
    return table


def load(cls: type[T], table: Any, where: str = "") -> T:
    """Build dataclass ``cls`` from ``table``, checking every key against its declaration."""
    declared = keys(cls)
    check_keys(table, declared, where)
    values = {name: value_of(declared[name], table[name], join(where, name)) for name in table}
    for key in declared.values():
        if key.required and key.name not in values:
            raise SettingError(join(where, key.name), f"missing; expected {type_text(key)}")
    try:
        return cls(**values)
    except SettingError as exc:
        raise exc.under(where) from None


def value_of(key: Key, value: Any, where: str) -> Any:
    """One TOML value for ``key``, converted and checked (see the module docstring for the rules)."""
    if key.declared.kind is not None:
        return key.declared.kind.parse(value, where)
    return _typed(_plain(key.hint), value, where, key.declared)


def _plain(hint: Any) -> Any:
    """``X | None`` -> ``X``."""
    if isinstance(hint, types.UnionType) or typing.get_origin(hint) is typing.Union:
        args = tuple(a for a in typing.get_args(hint) if a is not type(None))
        return args[0] if len(args) == 1 else args
    return hint


def _typed(hint: Any, value: Any, where: str, declared: Declared) -> Any:
    origin = typing.get_origin(hint)
    if dataclasses.is_dataclass(hint):
        return load(hint, value, where)
    if origin is tuple:
        if not isinstance(value, list):
            raise SettingError(where, f"expected a list, got {value!r}")
        item = _plain(typing.get_args(hint)[0])
        return tuple(_typed(item, v, f"{where}[{i}]", declared) for i, v in enumerate(value))
    if origin is Mapping or origin is dict:
        if not isinstance(value, Mapping):
            raise SettingError(where, f"expected a table, got {value!r}")
        item = _plain(typing.get_args(hint)[1])
        return types.MappingProxyType({k: _typed(item, v, join(where, k), declared) for k, v in value.items()})
    return check_value(declared, _scalar(hint, value, where), where, shown=value)


def _scalar(hint: Any, value: Any, where: str) -> Any:
    """A TOML value of scalar type ``hint`` (or one of a tuple of them); ints are accepted as floats."""
    allowed = hint if isinstance(hint, tuple) else (hint,)
    for kind in allowed:
        if kind is Any or kind is bool and isinstance(value, bool):
            return value
        if isinstance(value, bool):
            continue
        if kind is int and isinstance(value, int):
            return value
        if kind is float and isinstance(value, (int, float)):
            if not math.isfinite(value):
                raise SettingError(where, f"expected a finite number, got {value!r}")
            return float(value)
        if kind is str and isinstance(value, str):
            return value
    if not all(k in _SCALARS or k is Any for k in allowed):
        raise TypeError(f"{where}: unsupported setting type {hint!r}")
    raise SettingError(where, f"expected {' or '.join(_TYPE_TEXT[k] for k in allowed)}, got {value!r}")


def check_value(declared: Declared, value: Any, where: str, shown: Any = None) -> Any:
    """``value`` within the declared range or choices (the type is already right; ``shown``: as given)."""
    shown = value if shown is None else shown
    if declared.choices is not None and value not in declared.choices:
        near = near_miss(value, declared.choices) if isinstance(value, str) else None
        hint = f"; did you mean {near!r}?" if near else ""
        raise SettingError(where, f"expected one of {list(declared.choices)}, got {shown!r}{hint}")
    if declared.range is not None and not isinstance(value, bool) and isinstance(value, (int, float)):
        if value not in declared.range:
            raise SettingError(where, f"expected a value in {range_text(declared)}, got {shown!r}")
    return value


def check(obj: Any, where: str = "") -> None:
    """Every declared scalar of dataclass instance ``obj`` within its range or choices (direct construction)."""
    for name, hint, declared in _scalar_keys(type(obj)):
        value = getattr(obj, name)
        if value is not None:
            check_value(declared, _scalar(hint, value, join(where, name)), join(where, name), shown=value)


@functools.cache
def _scalar_keys(cls: type) -> tuple[tuple[str, Any, Declared], ...]:
    """(name, scalar type, declaration) of every plain scalar key of ``cls``: what :func:`check` checks."""
    return tuple((k.name, _plain(k.hint), k.declared) for k in keys(cls).values()
                 if k.declared.kind is None and _plain(k.hint) in _SCALARS)


_TYPE_TEXT = {bool: "true or false", int: "an integer", float: "a number", str: "a string", Any: "any value"}


def range_text(declared: Declared) -> str:
    """``[0, 1]`` or ``(0, 15] m/s^2``."""
    if declared.range is None:
        return ""
    return f"{declared.range} {declared.unit}" if declared.unit else str(declared.range)


def type_text(key: Key) -> str:
    """What the key's value is, in words (for errors and the reference)."""
    if key.declared.kind is not None:
        return key.declared.kind.name
    return _hint_text(_plain(key.hint))


def _hint_text(hint: Any) -> str:
    if isinstance(hint, tuple):
        return " or ".join(_hint_text(h) for h in hint)
    if dataclasses.is_dataclass(hint):
        return "a table"
    origin = typing.get_origin(hint)
    if origin is tuple:
        item = _plain(typing.get_args(hint)[0])
        return "a list of tables" if dataclasses.is_dataclass(item) else f"a list of {_hint_text(item)}"
    if origin is Mapping or origin is dict:
        return f"a table of name = {_hint_text(_plain(typing.get_args(hint)[1]))}"
    return _TYPE_TEXT.get(hint, str(hint))


def load_toml(path: Path, build: Callable[[dict], T], what: str) -> T:
    """``build(parsed TOML)``; a missing file, bad TOML or a :class:`ConfigError` becomes one error naming the file."""
    try:
        data = tomllib.loads(Path(path).read_text())
    except FileNotFoundError:
        raise ConfigError(f"{path}: {what} file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{path}: cannot read the {what} file: {exc}") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: invalid TOML: {exc}") from None
    try:
        return build(data)
    except ConfigError as exc:
        raise ConfigError(f"{path}: {exc}") from None
