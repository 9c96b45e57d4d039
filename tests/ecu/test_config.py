"""EcuConfig: defaults, strict loading, key paths in errors."""

import dataclasses

import pytest

from ecu import ConfigError, EcuConfig
from ecu.core import CoreParams


def test_defaults_and_strategy_fractions():
    assert EcuConfig().strategy == "tightening"
    assert {s: EcuConfig(strategy=s).model_decel_mps2 for s in ("none", "conservative", "tightening")} == \
        pytest.approx({"none": 8.1, "conservative": 7.2, "tightening": 8.1})
    assert isinstance(EcuConfig(), CoreParams)
    with pytest.raises(dataclasses.FrozenInstanceError):
        EcuConfig().standoff_m = 3.0  # type: ignore[misc]


def test_unknown_key_is_named_with_a_suggestion():
    with pytest.raises(ConfigError, match=r"scenario\.ecu\.standof_m: unknown key; did you mean scenario\.ecu\.standoff_m"):
        EcuConfig.from_dict({"standof_m": 3.0}, where="scenario.ecu")


@pytest.mark.parametrize("key,value,pattern", [
    ("peak_decel_mps2", -1.0, r"ecu\.peak_decel_mps2: expected a value in \(0\.0, 15\.0\], got -1\.0"),
    ("strategy", "fast", r"ecu\.strategy: expected one of \['none', 'conservative', 'tightening', 'adaptive'\], got 'fast'"),
    ("fault_recovery_cycles", 0, r"ecu\.fault_recovery_cycles: expected a value in \[1, 100000\], got 0"),
    ("standoff_m", "2", r"ecu\.standoff_m: expected a number, got '2'"),
])
def test_bad_values_give_expected_and_actual(key, value, pattern):
    with pytest.raises(ConfigError, match=pattern):
        EcuConfig.from_dict({key: value})


def test_from_toml_with_ecu_table_and_top_level(tmp_path):
    table = tmp_path / "a.toml"
    table.write_text('[ecu]\nstrategy = "none"\npeak_decel_mps2 = 8\n')
    cfg = EcuConfig.from_toml(table)
    assert (cfg.strategy, cfg.peak_decel_mps2, cfg.model_decel_mps2) == ("none", 8.0, pytest.approx(7.2))
    flat = tmp_path / "b.toml"
    flat.write_text('standoff_m = 3.5\nbogus = 1\n')
    with pytest.raises(ConfigError, match=r"b\.toml\.bogus: unknown key"):
        EcuConfig.from_toml(flat)
