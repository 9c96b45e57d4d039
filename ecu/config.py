"""``EcuConfig``: the ECU's configuration, a frozen dataclass loaded from TOML or a mapping.

``EcuConfig`` *is* the core's :class:`~ecu.core.params.CoreParams` (every
number the arithmetic uses, with defaults) plus the shell's own settings
(``status_period_cycles``, ``sim_time``, ``key_file``, ``equipment``). It is passed to the core directly.

Every key is declared once, on its field (:func:`ecu.settings.setting`: type,
unit, range or choices, default, doc), and loaded by the one loader of crd
(:func:`ecu.settings.load`): an unknown key, a value of the wrong type or out
of its range raises :class:`~ecu.settings.SettingError` (a
:class:`~ecu.errors.ConfigError`) naming the key path, the expected and the
actual value, and for a near miss the valid key. Direct construction checks
the same declarations. A value that contradicts the CAN contract is refused
the same way (:func:`_check_contract`): ``cycle_s`` must be the DBC's cycle of
``SafetyOverride`` (the master steps the ECU at that cycle, so another value
would make the core compute hold times and slope limits with the wrong time
step), ``status_period_cycles`` must give ``EcuStatus``'s DBC cycle, and a
reception timeout may not be shorter than its message's cycle. Nothing comes
from the environment.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

from can_dbc.contract import ECU_CYCLE_S, cycle_time_s

from . import settings
from .core.params import CoreParams
from .equipment import DEFAULT as DEFAULT_EQUIPMENT, EQUIPMENT
from .settings import Range, SettingError, setting

#: EcuStatus is sent every this many ECU cycles (DBC: 100 ms / 10 ms)
STATUS_PERIOD_CYCLES = round(cycle_time_s("EcuStatus") / ECU_CYCLE_S)
#: reception timeout key -> the message it times out
_TIMEOUTS = {"wheel_speeds_timeout_s": "WheelSpeeds", "driver_input_timeout_s": "DriverInput",
             "object_timeout_s": "ObjectTrack"}
#: the table of a scenario file that holds the ECU's settings
SECTION = "ecu"


@dataclass(frozen=True, slots=True)
class EcuConfig(CoreParams):
    """Strategy, core parameters and node settings. Construct directly or via the loaders."""

    status_period_cycles: int = setting(STATUS_PERIOD_CYCLES, unit="cycles", allowed=Range(1, 100_000),
                                        doc="EcuStatus is sent every this many cycles (DBC: 100 ms = 10 cycles)")
    sim_time: bool = setting(False, doc="one cycle per received SimClock frame instead of on the wall clock")
    key_file: str = setting("", doc="SecOC key file (32 hex digits, mode 0600; can_dbc.secoc); "
                                    "empty: E2E protection only")
    equipment: str = setting(DEFAULT_EQUIPMENT, allowed=tuple(EQUIPMENT),
                             doc="which frames the ECU receives and sends (ecu.equipment): " + "; ".join(
                                 f"{e.name}: {e.doc}" for e in EQUIPMENT.values()) + ". In a scenario the "
                                 "scene gives it (Scenario.equipment); stated, it must be the scene's")

    def __post_init__(self) -> None:
        settings.check(self)
        _check_contract(self)
        _steering_from_equipment(self)
        CoreParams.__post_init__(self)

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        return tuple(settings.keys(cls))

    @classmethod
    def from_dict(cls, mapping: Mapping[str, Any], where: str = SECTION) -> "EcuConfig":
        """Build from a mapping (e.g. a TOML table); ``where`` is the key path of the table in errors."""
        return settings.load(cls, mapping, where)

    @classmethod
    def from_toml(cls, path: str | Path) -> "EcuConfig":
        """Load ``path``: a scenario file's ``[ecu]`` table, or an ECU file with the keys at top level.

        A scenario's other tables are the scenario's, checked by its own loader (``cosim``, which
        ``ecu`` does not import); a scenario without ``[ecu]`` runs the ECU's defaults, as it does
        in the co-simulation. Errors read ``<file>: ecu.<key>: <problem>``.
        """
        return settings.load_toml(Path(path), _from_file, "ECU configuration")


def _from_file(data: Mapping[str, Any]) -> EcuConfig:
    if SECTION in data:
        return EcuConfig.from_dict(data[SECTION], SECTION)
    if data and all(isinstance(value, (Mapping, list)) for value in data.values()):  # a scenario without [ecu]
        for name in data:
            if settings.near_miss(name, (SECTION,)):
                raise SettingError(name, f"unknown key; did you mean {SECTION}?")
        return EcuConfig()
    return EcuConfig.from_dict(data, "")


def _steering_from_equipment(config: EcuConfig) -> None:
    """Steering authority is the equipment's (``planar_steering`` sends SteeringOverride); a stated
    ``steering_authority`` gives way to it, so that a configuration whose equipment changes stays whole."""
    steers = EQUIPMENT[config.equipment].steering
    if config.steering_authority != steers:
        object.__setattr__(config, "steering_authority", steers)


def _check_contract(config: EcuConfig) -> None:
    """Refuse values that contradict the DBC (see the module docstring)."""
    if abs(config.cycle_s - ECU_CYCLE_S) > 1e-12:
        raise SettingError("cycle_s", f"expected {ECU_CYCLE_S} s, the DBC's GenMsgCycleTime of SafetyOverride "
                                      f"at which the ECU is stepped, got {config.cycle_s!r}")
    if config.status_period_cycles != STATUS_PERIOD_CYCLES:
        raise SettingError("status_period_cycles", f"expected {STATUS_PERIOD_CYCLES} (the DBC's EcuStatus "
                           f"cycle of {cycle_time_s('EcuStatus')} s), got {config.status_period_cycles!r}")
    for key, message in _TIMEOUTS.items():
        value, cycle = getattr(config, key), cycle_time_s(message)
        if value < cycle:
            raise SettingError(key, f"expected at least {cycle} s, {message}'s DBC cycle, got {value!r}")
