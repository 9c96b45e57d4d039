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
    with pytest.raises(ConfigError, match=r"^scenario\.ecu\.standof_m: unknown key; did you mean scenario\.ecu\.standoff_m\?$"):
        EcuConfig.from_dict({"standof_m": 3.0}, where="scenario.ecu")


@pytest.mark.parametrize("key,value,pattern", [
    ("peak_decel_mps2", -1.0, r"^ecu\.peak_decel_mps2: expected a value in \(0, 15\] m/s\^2, got -1\.0$"),
    ("strategy", "fast", r"^ecu\.strategy: expected one of \['none', 'conservative', 'tightening', 'adaptive'\], got 'fast'$"),
    ("strategy", "tight", r"^ecu\.strategy: expected one of \[.*\], got 'tight'; did you mean 'tightening'\?$"),
    ("fault_recovery_cycles", 0, r"^ecu\.fault_recovery_cycles: expected a value in \[1, 100000\] cycles, got 0$"),
    ("fault_recovery_cycles", 1.5, r"^ecu\.fault_recovery_cycles: expected an integer, got 1\.5$"),
    ("standoff_m", "2", r"^ecu\.standoff_m: expected a number, got '2'$"),
    ("cycle_s", 0.02, r"^ecu\.cycle_s: expected 0\.01 s, the DBC's GenMsgCycleTime of SafetyOverride .*, got 0\.02$"),
    ("object_timeout_s", 0.01, r"^ecu\.object_timeout_s: expected at least 0\.05 s, ObjectTrack's DBC cycle, got 0\.01$"),
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
    with pytest.raises(ConfigError, match=r"b\.toml: bogus: unknown key; expected one of strategy, cycle_s, "):
        EcuConfig.from_toml(flat)
    flat.write_text('standoff_m = 3.5\n')
    assert EcuConfig.from_toml(flat).standoff_m == 3.5


def test_from_toml_reads_a_scenario_files_ecu_table(tmp_path):
    """Issue 25: ``crd ecu --config scenario.toml`` reads the scenario's [ecu]; its other tables are the scenario's."""
    scenario = tmp_path / "scenario.toml"
    scenario.write_text('[scenario]\nname = "x"\n[plant]\nroad_friction = 0.5\n[[objects]]\nposition_m = 80.0\n'
                        '[ecu]\nstrategy = "conservative"\npeak_decel_mps2 = 6.5\n')
    cfg = EcuConfig.from_toml(scenario)
    assert (cfg.strategy, cfg.peak_decel_mps2) == ("conservative", 6.5)
    scenario.write_text('[scenario]\nname = "x"\n[ecu]\npeak_decel = 6.5\n')
    with pytest.raises(ConfigError, match=r"scenario\.toml: ecu\.peak_decel: unknown key; did you mean ecu\.peak_decel_mps2\?$"):
        EcuConfig.from_toml(scenario)
    scenario.write_text('[scenario]\nname = "x"\n[driver]\nmodel = "cruise"\n')  # no [ecu]: the ECU's defaults
    assert EcuConfig.from_toml(scenario) == EcuConfig()
    scenario.write_text('[scenario]\nname = "x"\n[ecuu]\nstrategy = "none"\n')  # a near miss is not ignored
    with pytest.raises(ConfigError, match=r"scenario\.toml: ecuu: unknown key; did you mean ecu\?$"):
        EcuConfig.from_toml(scenario)


def test_direct_construction_checks_the_same_declarations():
    with pytest.raises(ConfigError, match=r"^peak_decel_mps2: expected a value in \(0, 15\] m/s\^2, got 20\.0$"):
        EcuConfig(peak_decel_mps2=20.0)
    with pytest.raises(ConfigError, match=r"^abs_slip_cycles: expected an integer, got 2\.5$"):
        EcuConfig(abs_slip_cycles=2.5)  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"^driven_axle: expected one of \['front', 'rear', 'all'\], got 'back'$"):
        dataclasses.replace(EcuConfig(), driven_axle="back")


def test_every_core_parameter_declares_its_key():
    """CoreParams' fields carry unit/range/choices and doc; the loader refuses nothing else."""
    from ecu.settings import keys

    declared = keys(EcuConfig)
    assert set(declared) == set(EcuConfig.keys()) and len(declared) > 40
    for key in declared.values():
        assert key.declared.doc, key.name
        assert key.declared.range or key.declared.choices or key.hint in (bool, str), key.name
