"""Scenario loader: strict keys with suggestions, ranges, round trip of the resolved file."""

import tomllib

import pytest

from cosim.errors import ConfigError
from cosim.scenarios.loader import load_scenario, scenario_from_dict
from cosim.scenarios.resolve import scenario_to_toml
from cosim.cli.paper import PAPER_SCENARIO


@pytest.mark.parametrize("data, path, suggestion", [
    ({"scenario": {"duraton_s": 3.0}}, "scenario.duraton_s", "scenario.duration_s"),
    ({"plant": {"inputs": {"throtle": "x"}}}, "plant.inputs.throtle", "plant.inputs.throttle"),
    ({"radar": {"latency": 0.1}}, "radar.latency", "radar.latency_s"),
    ({"objct": {}}, "objct", "object"),
    ({"ecu": {"standof_m": 3.0}}, "ecu.standof_m", "ecu.standoff_m"),
    ({"objects": [{}, {"sped_mps": 1.0}]}, "objects[1].sped_mps", "objects[1].speed_mps"),
    ({"plant": {"inputs": {"throttle": {"nme": "x"}}}}, "plant.inputs.throttle.nme", "plant.inputs.throttle.name"),
])
def test_unknown_key_names_path_and_suggests(data, path, suggestion):
    with pytest.raises(ConfigError) as err:
        scenario_from_dict(data)
    assert str(err.value) == f"{path}: unknown key; did you mean {suggestion}?"


@pytest.mark.parametrize("data, fragment", [
    ({"radar": {"max_range_m": 500.0}}, "radar.max_range_m: expected a value in [1, 250] m, got 500.0"),
    ({"scenario": {"step_s": 0.003}}, "scenario.step_s"),
    ({"radar": {"dropout_probability": -0.1}}, "radar.dropout_probability"),
    ({"driver": {"model": "cruse"}}, "did you mean 'cruise'"),
    ({"scenario": {"seed": 1.5}}, "scenario.seed: expected an integer"),
    ({"ecu": {"strategy": "tight"}}, "ecu.strategy"),
    ({"driver": {"model": "scripted", "points": [[0, 0, 0], [0, 1, 1]]}}, "driver.points[1]"),
])
def test_out_of_range_and_bad_values(data, fragment):
    with pytest.raises(ConfigError) as err:
        scenario_from_dict(data)
    assert fragment in str(err.value)


def test_third_party_fmu_needs_mappings():
    with pytest.raises(ConfigError, match="plant.inputs"):
        scenario_from_dict({"plant": {"fmu": "x.fmu", "inputs": {"throttle": "t"}, "outputs": {"position": "p"}}})


def test_file_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[scenario]\nduration = 3\n")
    with pytest.raises(ConfigError, match=r"bad.toml: scenario.duration: unknown key; did you mean scenario.duration_s\?$"):
        load_scenario(bad)
    with pytest.raises(ConfigError, match="not found"):
        load_scenario(tmp_path / "missing.toml")


def test_paper_scenario_loads_and_resolved_round_trips():
    sc = load_scenario(PAPER_SCENARIO)
    assert sc.object.position_m == 225.0 and sc.driver.model == "full_throttle"
    again = scenario_from_dict(tomllib.loads(scenario_to_toml(sc)))
    assert again == sc


def test_ecu_section_contradicting_the_contract_is_refused_at_load(tmp_path):
    # issue 10: [ecu] cycle_s = 0.02 loaded, while the master steps the ECU every 10 ms
    path = tmp_path / "slow_ecu.toml"
    path.write_text('[ecu]\nstrategy = "none"\ncycle_s = 0.02\n')
    with pytest.raises(ConfigError, match=r"slow_ecu.toml: ecu.cycle_s: expected 0.01 s.*got 0.02"):
        load_scenario(path)
    path.write_text('[ecu]\npeak_decel_mps2 = -1.0\n')
    with pytest.raises(ConfigError, match=r"slow_ecu.toml: ecu.peak_decel_mps2"):
        load_scenario(path)


def test_start_time_default_and_offset_datetimes():
    default = scenario_from_dict({}).scenario
    assert default.start_time == "2020-01-01T00:00:00+00:00" and default.start_datetime.year == 2020
    toml = tomllib.loads("[scenario]\nstart_time = 2024-05-01T08:30:00+02:00\n")
    sc = scenario_from_dict(toml)
    assert sc.scenario.start_time == "2024-05-01T08:30:00+02:00"
    assert scenario_from_dict({"scenario": {"start_time": "2024-05-01T06:30:00Z"}}).scenario.start_datetime \
        == sc.scenario.start_datetime
    assert scenario_from_dict(tomllib.loads(scenario_to_toml(sc))) == sc  # the resolved file repeats it


@pytest.mark.parametrize("toml, fragment", [
    ("start_time = 2024-05-01T08:30:00", "got 2024-05-01T08:30:00 (no offset)"),
    ("start_time = 1970-01-01T00:00:00Z", "expected a date from 1990 to 2099, got 1970-01-01T00:00:00+00:00"),
    ('start_time = "yesterday"', "got 'yesterday'"),
    ("start_time = 5", "got 5"),
])
def test_bad_start_time_names_the_key(toml, fragment):
    with pytest.raises(ConfigError) as err:
        scenario_from_dict(tomllib.loads("[scenario]\n" + toml + "\n"))
    assert str(err.value).startswith("scenario.start_time: expected") and fragment in str(err.value)


def test_ecu_and_plant_nest_the_same_way():
    """[ecu] holds EcuConfig's keys directly, like every section; [plant.parameters] is one declared table."""
    from cosim.scenarios.resolve import DERIVED_ECU_KEYS
    from ecu import EcuConfig

    sc = scenario_from_dict({"ecu": {"strategy": "none", "peak_decel_mps2": 6.5},
                             "plant": {"parameters": {"brake_dead_time": 0.15, "n": 2, "on": True}}})
    assert sc.ecu == EcuConfig(strategy="none", peak_decel_mps2=6.5)
    assert dict(sc.plant.parameters) == {"brake_dead_time": 0.15, "n": 2, "on": True}
    resolved = tomllib.loads(scenario_to_toml(sc))
    # every key but those the scene gives (ecu.equipment: read back, the scene gives it again)
    assert set(resolved["ecu"]) == set(EcuConfig.keys()) - {"equipment"} and DERIVED_ECU_KEYS == ("equipment",)
    assert resolved["ecu"]["peak_decel_mps2"] == 6.5
    assert resolved["plant"]["parameters"] == {"brake_dead_time": 0.15, "n": 2, "on": True}
    assert scenario_from_dict(resolved) == sc
    with pytest.raises(ConfigError, match=r"^plant\.parameters\.x: expected a scalar, got \[1\]$"):
        scenario_from_dict({"plant": {"parameters": {"x": [1]}}})


def test_paper_strategies_are_one_list():
    from can_dbc.contract import STRATEGIES
    from cosim.results import paper_claims
    from cosim.scenarios.config import PAPER_STRATEGIES

    assert paper_claims.REQUIRED is PAPER_STRATEGIES and set(PAPER_STRATEGIES) < set(STRATEGIES)
