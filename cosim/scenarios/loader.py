"""Scenario TOML → :class:`~cosim.scenarios.config.Scenario`, strictly.

The sections are read by the one loader of crd (:func:`ecu.settings.load`)
against the keys their dataclasses declare (:mod:`cosim.scenarios.config`,
and :class:`ecu.EcuConfig` for ``[ecu]``): an unknown key, a value of the
wrong type or outside its range is a :class:`~cosim.errors.ConfigError` naming
the key path (``plant.inputs.throtle``), the expected and the actual value,
and for a near miss the closest valid key. ``[ecu]`` is checked at load like
every section, including its agreement with the DBC (no ``cycle_s`` other
than the contract's 10 ms). What this module adds are the rules that span
keys: the builtin plant's default maps, a third-party FMU's mandatory maps,
``[object]`` versus ``[[objects]]``, a plant step that divides the ECU cycle, and an
``[ecu] equipment``, if stated, that is the scene's (``Scenario.equipment``).
Every error of a file names the file (:func:`load_scenario`).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any, Mapping

from can_dbc.contract import ECU_CYCLE_S
from ecu.settings import SettingError, load, load_toml

from .config import (
    BUILTIN_INITIAL, BUILTIN_INPUTS, BUILTIN_OUTPUTS, BUILTIN_PLANAR_INITIAL, BUILTIN_PLANAR_INPUTS,
    BUILTIN_PLANAR_OUTPUTS, ObjectConfig, PlantConfig, Scenario,
)
from .planar_rules import check_planar, with_target_boxes


def _merge_builtin(plant: PlantConfig, given: Mapping[str, Any], planar: bool) -> PlantConfig:
    """The builtin plant has default mappings (its planar ones in a planar scenario); a given role replaces its default."""
    extra_in, extra_out, extra_initial = (BUILTIN_PLANAR_INPUTS, BUILTIN_PLANAR_OUTPUTS, BUILTIN_PLANAR_INITIAL) \
        if planar else ((), (), ())
    inputs = {m.role: m for m in BUILTIN_INPUTS + extra_in} | {m.role: m for m in plant.inputs if "inputs" in given}
    if "accel_command" in inputs:
        raise SettingError("plant.inputs.accel_command",
                           "the builtin plant takes throttle and brake, not accel_command")
    outputs = {m.role: m for m in BUILTIN_OUTPUTS + extra_out} | {m.role: m for m in plant.outputs if "outputs" in given}
    initial = {m.role: m for m in BUILTIN_INITIAL + extra_initial} | \
        {m.role: m for m in plant.initial if "initial" in given}
    return dataclasses.replace(plant, inputs=tuple(inputs.values()), outputs=tuple(outputs.values()),
                               initial=tuple(initial.values()))


def _third_party(plant: PlantConfig, given: Mapping[str, Any], base_dir: Path | None) -> PlantConfig:
    """A third-party FMU: maps required, no builtin ``[plant.initial]``, its path relative to the file."""
    missing = [name for name in ("inputs", "outputs") if name not in given]
    if missing:
        raise SettingError(f"plant.{missing[0]}", "missing; a third-party FMU needs [plant.inputs] and "
                                                  "[plant.outputs]")
    if base_dir is not None and not Path(plant.fmu).is_absolute():
        plant = dataclasses.replace(plant, fmu=str((base_dir / plant.fmu).resolve()))
    if "initial" not in given:
        plant = dataclasses.replace(plant, initial=())
    return plant


def _check_initial(plant: PlantConfig) -> None:
    """Each initial value that is set needs its [plant.initial] map, and is not also a start value."""
    roles = {m.role: m for m in plant.initial}
    for key, role, _ in plant.initial_values():
        if role not in roles:
            raise SettingError(f"plant.{key}", f"this FMU has no [plant.initial] {role} mapping;"
                                               f" expected [plant.initial] {role} = \"<parameter name>\"")
        name = roles[role].names[0]
        if name in plant.parameters:
            raise SettingError(f"plant.parameters.{name}", f"set by plant.{key} through "
                                                           f"[plant.initial] {role}; expected only one of the two")



def _check_plant_roles(plant: PlantConfig) -> None:
    roles_in = {m.role for m in plant.inputs}
    if "accel_command" in roles_in and roles_in & {"throttle", "brake"}:
        raise SettingError("plant.inputs", "expected either accel_command or throttle/brake, got both")
    if "accel_command" not in roles_in and not {"throttle", "brake"} <= roles_in:
        raise SettingError("plant.inputs", f"expected throttle and brake (or accel_command), got {sorted(roles_in)}")
    missing = {"position", "speed"} - {m.role for m in plant.outputs}
    if missing:
        raise SettingError("plant.outputs", f"expected position and speed to be mapped, missing {sorted(missing)}")


def _objects(scenario: Scenario, data: Mapping[str, Any]) -> Scenario:
    """``[[objects]]``: one or more tables; with it, the single ``[object]`` is disabled."""
    if "objects" not in data:
        return with_target_boxes(scenario, data)
    if "object" in data:
        raise SettingError("objects", "expected either [object] or [[objects]], got both")
    if not scenario.objects:
        raise SettingError("objects", "expected one or more [[objects]] tables, got []")
    return with_target_boxes(dataclasses.replace(scenario, object=ObjectConfig(enabled=False)), data)


def scenario_from_dict(data: Mapping[str, Any], base_dir: Path | None = None) -> Scenario:
    """Build and check a :class:`Scenario` from parsed TOML.

    A relative ``plant.fmu`` path is resolved against ``base_dir``.
    """
    scenario = _objects(load(Scenario, data), data)
    plant, given = scenario.plant, data.get("plant", {})
    plant = _merge_builtin(plant, given, scenario.planar) if plant.fmu == "builtin" else \
        _third_party(plant, given, base_dir)
    _check_plant_roles(plant)
    _check_initial(plant)
    check_planar(dataclasses.replace(scenario, plant=plant), data)
    cycles = ECU_CYCLE_S / scenario.scenario.step_s
    if abs(cycles - round(cycles)) > 1e-9:
        raise SettingError("scenario.step_s", f"expected a divisor of the {ECU_CYCLE_S} s ECU cycle, "
                                              f"got {scenario.scenario.step_s!r}")
    scenario = dataclasses.replace(scenario, plant=plant)
    _check_equipment(scenario, data.get("ecu", {}))
    if scenario.driver.reaction_time_min_s > scenario.driver.reaction_time_max_s:
        raise SettingError("driver.reaction_time_min_s", f"expected at most driver.reaction_time_max_s "
                                                         f"({scenario.driver.reaction_time_max_s}), got "
                                                         f"{scenario.driver.reaction_time_min_s}")
    return scenario


def _check_equipment(scenario: Scenario, given: Mapping[str, Any]) -> None:
    """``[ecu] equipment`` need not be stated: the scene gives it (``Scenario.equipment``); stated, it must be it."""
    if "equipment" in given and scenario.ecu.equipment != scenario.equipment:
        raise SettingError("ecu.equipment", f"expected {scenario.equipment!r}, what this scene equips the ECU with "
                                            f"(ecu.equipment), got {scenario.ecu.equipment!r}")


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario TOML file; errors are :class:`ConfigError` with the file name."""
    path = Path(path)
    return load_toml(path, lambda data: scenario_from_dict(data, base_dir=path.parent), "scenario")
