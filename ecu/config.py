"""``EcuConfig``: the ECU's configuration, a frozen dataclass loaded from TOML or a mapping.

``EcuConfig`` *is* the core's :class:`~ecu.core.params.CoreParams` (every
number the arithmetic uses, with defaults) plus the shell's own settings
(``status_period_cycles``, ``sim_time``). It is passed to the core directly.

Loading is strict: an unknown key raises :class:`~ecu.errors.ConfigError`
naming the key path and the nearest valid name (``difflib``); a value of the
wrong type or outside its range raises ``ConfigError`` with the expected and
the actual value. A value that contradicts the CAN contract is refused the
same way (:func:`_check_contract`): ``cycle_s`` must be the DBC's cycle of
``SafetyOverride`` (the master steps the ECU at that cycle, so another value
would make the core compute hold times and slope limits with the wrong time
step), ``status_period_cycles`` must give ``EcuStatus``'s DBC cycle, a
reception timeout may not be shorter than its message's cycle, and no
deceleration may exceed the full scale of ``BrakeDecelRequest``. Nothing
comes from the environment.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, Mapping

from can_dbc.contract import BRAKE_DECEL_MAX_MPS2, ECU_CYCLE_S, STRATEGIES, cycle_time_s

from .core.params import NON_DRIVEN_WHEELS, CoreParams
from .errors import ConfigError

#: EcuStatus is sent every this many ECU cycles (DBC: 100 ms / 10 ms)
STATUS_PERIOD_CYCLES = round(cycle_time_s("EcuStatus") / ECU_CYCLE_S)
#: reception timeout key -> the message it times out
_TIMEOUTS = {"wheel_speeds_timeout_s": "WheelSpeeds", "driver_input_timeout_s": "DriverInput",
             "object_timeout_s": "ObjectTrack"}

_POSITIVE = (0.0, math.inf, False)  # (low, high, low inclusive)
#: key -> (low, high, low inclusive); high is always inclusive.
_RANGES: dict[str, tuple[float, float, bool]] = {
    "cycle_s": (0.0, 1.0, False),
    "actuation_latency_s": (0.0, 5.0, True),
    "peak_decel_mps2": (0.0, BRAKE_DECEL_MAX_MPS2, False),
    "none_decel_fraction": (0.0, 1.0, False),
    "conservative_decel_fraction": (0.0, 1.0, False),
    "tightening_decel_fraction": (0.0, 1.0, False),
    "standoff_m": (0.0, 100.0, True),
    "driver_max_accel_mps2": (0.0, 20.0, False),
    "proximity_margin_m": (0.0, 250.0, False),
    "contingency_decel_mps2": (0.0, BRAKE_DECEL_MAX_MPS2, False),
    "contingency_release_ratio": (1.0, 10.0, True),
    "contingency_release_speed_mps": (0.0, 1000.0, True),
    "decel_estimate_floor_mps2": (0.0, 15.0, False),
    "decel_estimate_time_constant_s": _POSITIVE,
    "decel_filter_time_constant_s": _POSITIVE,
    "abs_slip_threshold": (0.0, 1.0, False),
    "abs_slip_cycles": (1, 1000, True),
    "decel_settle_cycles": (0, 100_000, True),
    "decel_shortfall_mps2": (0.0, 15.0, False),
    "driven_axle_load_share": (0.0, 1.0, False),
    "decel_estimate_min_speed_mps": (0.0, 100.0, True),
    "speed_slope_margin_mps2": (0.0, 50.0, True),
    "brake_memory_s": (0.0, 10.0, True),
    "moving_object_speed_mps": (0.0, 100.0, True),
    "standstill_speed_mps": (0.0, 10.0, True),
    "vehicle_width_m": (0.0, 10.0, False),
    "path_margin_m": (0.0, 20.0, True),
    "proximity_time_s": (0.0, 10.0, True),
    "proximity_margin_min_m": (0.0, 250.0, False),
    "wheel_speeds_timeout_s": _POSITIVE,
    "driver_input_timeout_s": _POSITIVE,
    "object_timeout_s": _POSITIVE,
    "e2e_invalid_score": (1, 5, True),
    "fault_recovery_cycles": (1, 100_000, True),
    "status_period_cycles": (1, 100_000, True),
    "wheel_slip_abs_mps": (0.0, 100.0, True),
    "wheel_slip_fraction": (0.0, 1.0, True),
    "radar_speed_tolerance_mps": (0.0, 100.0, True),
    "pedal_conflict_fraction": (0.0, 1.0, True),
    "degraded_decel_fraction": (0.0, 1.0, False),
}
_CHOICES: dict[str, tuple[str, ...]] = {
    "strategy": STRATEGIES,
    "driven_axle": tuple(NON_DRIVEN_WHEELS),
}
_INTEGERS = {"abs_slip_cycles", "decel_settle_cycles", "e2e_invalid_score", "fault_recovery_cycles", "status_period_cycles"}


@dataclass(frozen=True, slots=True)
class EcuConfig(CoreParams):
    """Strategy, core parameters and node settings. Construct directly or via the loaders."""

    #: ``EcuStatus`` is sent every this many cycles (DBC: 100 ms = 10 cycles).
    status_period_cycles: int = STATUS_PERIOD_CYCLES
    #: run() performs one cycle per received ``SimClock`` frame instead of on the wall clock.
    sim_time: bool = False
    #: SecOC key file (32 hex digits, mode 0600; ``can_dbc.secoc``); empty: E2E protection only.
    key_file: str = ""

    def __post_init__(self) -> None:
        _validate(self, "ecu")
        _check_contract(self, "ecu")
        CoreParams.__post_init__(self)

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls) if f.init)

    @classmethod
    def from_dict(cls, mapping: Mapping[str, Any], where: str = "ecu") -> "EcuConfig":
        """Build from a mapping (e.g. a TOML table); ``where`` prefixes key paths in errors."""
        if not isinstance(mapping, Mapping):
            raise ConfigError(f"{where}: expected a table, got {type(mapping).__name__}")
        valid = cls.keys()
        for key in mapping:
            if key not in valid:
                import difflib  # here: only a bad key needs it (1 ms less at every ECU start)

                near = difflib.get_close_matches(str(key), valid, n=1)
                hint = f"; did you mean {where}.{near[0]}?" if near else ""
                raise ConfigError(f"{where}.{key}: unknown key{hint} (valid keys: {', '.join(valid)})")
        values = {key: _coerced(f"{where}.{key}", key, value) for key, value in mapping.items()}
        try:
            return cls(**values)
        except ConfigError as exc:
            raise ConfigError(str(exc).replace("ecu.", f"{where}.", 1)) from None

    @classmethod
    def from_toml(cls, path: str | Path) -> "EcuConfig":
        """Load ``path``; the settings sit at top level or in an ``[ecu]`` table (a scenario file's other
        tables are the scenario's: not read here)."""
        path = Path(path)
        try:
            data = tomllib.loads(path.read_text())
        except (OSError, tomllib.TOMLDecodeError) as exc:
            raise ConfigError(f"{path}: cannot read TOML: {exc}") from exc
        if "ecu" in data and isinstance(data["ecu"], Mapping):
            return cls.from_dict(data["ecu"], where=f"{path}:ecu")
        return cls.from_dict(data, where=str(path))


def _coerced(path: str, key: str, value: Any) -> Any:
    """Type check: TOML integers are accepted where floats are expected, nothing else is coerced."""
    default = next(f.default for f in fields(EcuConfig) if f.name == key)
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise ConfigError(f"{path}: expected true or false, got {value!r}")
    elif isinstance(default, int):
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{path}: expected an integer, got {value!r}")
    elif isinstance(default, float):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(f"{path}: expected a number, got {value!r}")
        value = float(value)
    elif isinstance(default, str) and not isinstance(value, str):
        raise ConfigError(f"{path}: expected a string, got {value!r}")
    return value


def _validate(config: EcuConfig, where: str) -> None:
    for key, choices in _CHOICES.items():
        value = getattr(config, key)
        if value not in choices:
            raise ConfigError(f"{where}.{key}: expected one of {list(choices)}, got {value!r}")
    for key, (low, high, low_inclusive) in _RANGES.items():
        value = getattr(config, key)
        if key in _INTEGERS and (isinstance(value, bool) or not isinstance(value, int)):
            raise ConfigError(f"{where}.{key}: expected an integer, got {value!r}")
        ok_low = value >= low if low_inclusive else value > low
        if not (isinstance(value, (int, float)) and math.isfinite(value) and ok_low and value <= high):
            bracket = "[" if low_inclusive else "("
            raise ConfigError(f"{where}.{key}: expected a value in {bracket}{low}, {high}], got {value!r}")


def _check_contract(config: EcuConfig, where: str) -> None:
    """Refuse values that contradict the DBC (see the module docstring)."""
    if abs(config.cycle_s - ECU_CYCLE_S) > 1e-12:
        raise ConfigError(f"{where}.cycle_s: expected {ECU_CYCLE_S} s, the DBC's GenMsgCycleTime of "
                          f"SafetyOverride at which the ECU is stepped, got {config.cycle_s!r}")
    if config.status_period_cycles != STATUS_PERIOD_CYCLES:
        raise ConfigError(f"{where}.status_period_cycles: expected {STATUS_PERIOD_CYCLES} (the DBC's EcuStatus "
                          f"cycle of {cycle_time_s('EcuStatus')} s), got {config.status_period_cycles!r}")
    for key, message in _TIMEOUTS.items():
        value, cycle = getattr(config, key), cycle_time_s(message)
        if value < cycle:
            raise ConfigError(f"{where}.{key}: expected at least {cycle} s, {message}'s DBC cycle, got {value!r}")
