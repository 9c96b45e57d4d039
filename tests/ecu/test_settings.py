"""ecu.settings: the one loader and its one error format, on toy declarations."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

import pytest

from ecu.errors import ConfigError
from ecu.settings import Kind, Range, SettingError, check, keys, load, load_toml, setting, walk


def _twice(value: Any, where: str) -> int:
    if not isinstance(value, int):
        raise SettingError(where, f"expected an integer to double, got {value!r}")
    return 2 * value


@dataclass(frozen=True)
class Wheel:
    name: str = setting(doc="required name")
    radius_m: float = setting(0.3, unit="m", allowed=Range(0.0, 2.0, low_open=True), doc="radius")


@dataclass(frozen=True)
class Car:
    mode: str = setting("a", allowed=("alpha", "beta", "a"), doc="mode")
    count: int = setting(1, allowed=Range(1, 10), doc="count")
    on: bool = setting(False, doc="switch")
    gap_m: float | None = setting(None, unit="m", allowed=Range(0.0, math.inf), doc="optional")
    front: Wheel = setting(Wheel(name="f"), doc="a nested table")
    wheels: tuple[Wheel, ...] = setting((), doc="a list of tables")
    starts: Mapping[str, int | float] = setting(factory=dict, doc="a free mapping")
    doubled: int = setting(0, kind=Kind("an integer, doubled", _twice, lambda v: v // 2), doc="a kind")

    def __post_init__(self) -> None:
        if self.on and self.count > 5:
            raise SettingError("count", f"expected at most 5 while on, got {self.count}")


def test_loads_nested_tables_lists_mappings_and_kinds():
    car = load(Car, {"mode": "beta", "count": 3, "on": True, "gap_m": 4, "front": {"name": "x", "radius_m": 1},
                     "wheels": [{"name": "l"}, {"name": "r", "radius_m": 0.5}], "starts": {"v0": 3, "x": 1.5},
                     "doubled": 4})
    assert car.gap_m == 4.0 and isinstance(car.gap_m, float) and car.front == Wheel("x", 1.0)
    assert car.wheels == (Wheel("l", 0.3), Wheel("r", 0.5))
    assert dict(car.starts) == {"v0": 3, "x": 1.5} and isinstance(car.starts["v0"], int)
    assert car.doubled == 8
    assert [p for p, _ in walk(Car)][:6] == ["mode", "count", "on", "gap_m", "front", "front.name"]


@pytest.mark.parametrize("table, message", [
    ({"mdoe": "a"}, "mdoe: unknown key; did you mean mode?"),
    ({"front": {"name": "x", "radius": 1.0}}, "front.radius: unknown key; did you mean front.radius_m?"),
    ({"wheels": [{"name": "l"}, {"nam": "r"}]}, "wheels[1].nam: unknown key; did you mean wheels[1].name?"),
    ({"zzz": 1}, "zzz: unknown key; expected one of mode, count, on, gap_m, front, wheels, starts, doubled"),
    ({"count": 1.5}, "count: expected an integer, got 1.5"),
    ({"count": True}, "count: expected an integer, got True"),
    ({"on": 1}, "on: expected true or false, got 1"),
    ({"gap_m": "3"}, "gap_m: expected a number, got '3'"),
    ({"gap_m": math.inf}, "gap_m: expected a finite number, got inf"),
    ({"count": 11}, "count: expected a value in [1, 10], got 11"),
    ({"front": {"name": "x", "radius_m": 0}}, "front.radius_m: expected a value in (0, 2] m, got 0"),
    ({"gap_m": -1}, "gap_m: expected a value in [0, inf) m, got -1"),
    ({"mode": "alpah"}, "mode: expected one of ['alpha', 'beta', 'a'], got 'alpah'; did you mean 'alpha'?"),
    ({"front": {}}, "front.name: missing; expected a string"),
    ({"front": 3}, "front: expected a table, got 3"),
    ({"wheels": {"name": "x"}}, "wheels: expected a list, got {'name': 'x'}"),
    ({"starts": {"v0": "fast"}}, "starts.v0: expected an integer or a number, got 'fast'"),
    ({"doubled": 1.0}, "doubled: expected an integer to double, got 1.0"),
    ({"on": True, "count": 6}, "count: expected at most 5 while on, got 6"),
])
def test_every_error_is_one_line_naming_the_key_path(table, message):
    with pytest.raises(SettingError) as err:
        load(Car, table)
    assert str(err.value) == message and isinstance(err.value, ConfigError)


def test_path_prefix_and_file_name(tmp_path):
    with pytest.raises(SettingError, match=r"^car\.count: expected a value in \[1, 10\], got 0$"):
        load(Car, {"count": 0}, "car")
    with pytest.raises(SettingError, match=r"^car\.count: expected at most 5 while on"):  # from __post_init__
        load(Car, {"on": True, "count": 7}, "car")
    path = tmp_path / "c.toml"
    path.write_text("[car]\ncont = 2\n")
    build = lambda data: load(Car, data["car"], "car")  # noqa: E731
    with pytest.raises(ConfigError) as err:
        load_toml(path, build, "car")
    assert str(err.value) == f"{path}: car.cont: unknown key; did you mean car.count?"
    path.write_text("[car\n")
    with pytest.raises(ConfigError, match=r"c\.toml: invalid TOML"):
        load_toml(path, build, "car")
    with pytest.raises(ConfigError, match=r"nope\.toml: car file not found$"):
        load_toml(tmp_path / "nope.toml", build, "car")


def test_direct_construction_check_and_declarations():
    check(Car(count=3))
    with pytest.raises(SettingError, match=r"^count: expected a value in \[1, 10\], got 0$"):
        check(Car(count=0))
    declared = keys(Car)
    assert declared["front"].default == Wheel(name="f") and keys(Wheel)["name"].required
    assert declared["count"].declared.range == Range(1, 10) and declared["mode"].declared.choices == ("alpha", "beta", "a")
