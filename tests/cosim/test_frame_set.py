"""The frame set follows the equipment (ecu.equipment), in the closed loop.

A 1-D scene equips the ECU as ``longitudinal``: the bus carries DriverInput, WheelSpeeds and
SafetyOverride every cycle, ObjectTrack every 5th and EcuStatus every 10th, and no planar frame
(before: EscDynamics and SteeringOverride every cycle and RadarTrack0..7 every 5th, in every run).
A planar scene whose plant takes the ECU's steer_request (the builtin plant's) equips it as
``planar_steering``: those, plus EscDynamics and SteeringOverride every cycle, the eight
RadarTrack slots every 5th and the stopping region's EcuRegionStatus every 10th. The same in process and with the ECU in its own process (which adds
the SimClock that paces it and the ECU's EcuIdentity), each frame but EcuStatus followed by its
SecOC authenticator (the statuses have none). A stated ``[ecu] equipment`` must be the scene's, and the resolved file
leaves it to the scene.
"""

from __future__ import annotations

import dataclasses
from collections import Counter

import pytest

from can_dbc import AUTHENTICATORS, LAYOUTS, LAYOUTS_BY_ID
from can_dbc.planar import TRACK_SLOTS
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import ClosedLoop, ecu_config
from cosim.scenarios.loader import load_scenario, scenario_from_dict
from cosim.scenarios.resolve import scenario_to_dict, scenario_to_toml
from ecu.equipment import EQUIPMENT, equipment_for
from ecu.settings import SettingError

CYCLES = 20  # 0.2 s of each scene
ONE_D, PLANAR = "cosim/scenarios/paper_cyclist.toml", "cosim/scenarios/paper_cyclist_road.toml"
#: message -> frames in CYCLES cycles
LONGITUDINAL = {"DriverInput": CYCLES, "WheelSpeeds": CYCLES, "SafetyOverride": CYCLES,
                "ObjectTrack": CYCLES // 5, "EcuStatus": CYCLES // 10}
PLANAR_STEERING = {**LONGITUDINAL, "EscDynamics": CYCLES, "SteeringOverride": CYCLES,
                   **{name: CYCLES // 5 for name in TRACK_SLOTS}, "EcuRegionStatus": CYCLES // 10}


@pytest.fixture(scope="module")
def fmu():
    from fmu_plant.build import ensure_fmu

    return ensure_fmu(fmi_version=3)


def _counts(path: str, fmu, mode: str) -> tuple[Counter, Counter]:
    """The run's logged frames by message name, and its authenticators by the message they authenticate."""
    sc = load_scenario(path)
    sc = dataclasses.replace(sc, scenario=dataclasses.replace(sc.scenario, duration_s=CYCLES * 0.01))
    record = ClosedLoop(sc, fmu, ecu=EcuOptions(mode=mode, spare=False)).run()
    by_auth = {fid: name for name, fid in AUTHENTICATORS.items()}
    ids = Counter(f.arbitration_id for f in record.frames)
    data = Counter({LAYOUTS_BY_ID[fid].name: n for fid, n in ids.items() if fid in LAYOUTS_BY_ID})
    auth = Counter({by_auth[fid]: n for fid, n in ids.items() if fid in by_auth})
    assert sum(data.values()) + sum(auth.values()) == len(record.frames)  # nothing else on the bus
    return data, auth


@pytest.mark.parametrize("mode", ["inprocess", pytest.param("process", marks=pytest.mark.wallclock)])
@pytest.mark.parametrize("path, expected", [(ONE_D, LONGITUDINAL), (PLANAR, PLANAR_STEERING)], ids=["1d", "planar"])
def test_the_bus_carries_the_frames_of_the_scenes_equipment(fmu, mode, path, expected):
    data, auth = _counts(path, fmu, mode)
    # the lock-step link paces the ECU process, which announces itself in its first cycle (a standalone node)
    process = {"SimClock": CYCLES, "EcuIdentity": 1} if mode == "process" else {}
    assert dict(data) == {**expected, **process}
    # each frame followed by its authenticator, but the informational statuses (sent without one)
    assert dict(auth) == {name: n for name, n in data.items() if name not in ("EcuStatus", "EcuRegionStatus")}


def test_the_scene_gives_the_equipment():
    assert load_scenario(ONE_D).equipment == "longitudinal" and load_scenario(PLANAR).equipment == "planar_steering"
    assert ecu_config(load_scenario(PLANAR), "none").equipment == "planar_steering"  # what the run's ECU gets
    assert [equipment_for(p, s).name for p, s in ((False, False), (True, False), (True, True), (False, True))] == \
        ["longitudinal", "planar", "planar_steering", "longitudinal"]  # no steering without the planar sensors
    assert EQUIPMENT["planar"].inputs[-9:] == ("EscDynamics", *TRACK_SLOTS)
    assert all(name in LAYOUTS for e in EQUIPMENT.values() for name in (*e.inputs, *e.requests))


def test_a_stated_equipment_must_be_the_scenes():
    import tomllib
    from pathlib import Path

    data = tomllib.loads(Path(PLANAR).read_text())
    stated = scenario_from_dict({**data, "ecu": {**data.get("ecu", {}), "equipment": "planar_steering"}})
    assert stated.ecu.equipment == "planar_steering"
    with pytest.raises(SettingError, match=r"ecu.equipment: expected 'planar_steering', what this scene equips "
                                           r"the ECU with \(ecu.equipment\), got 'longitudinal'"):
        scenario_from_dict({**data, "ecu": {**data.get("ecu", {}), "equipment": "longitudinal"}})
    with pytest.raises(SettingError, match="ecu.equipment: expected one of"):
        scenario_from_dict({**data, "ecu": {"equipment": "steering"}})
    assert "equipment" not in scenario_to_dict(stated)["ecu"]  # the scene gives it: sweeps' run keys stay
    resolved = tomllib.loads(scenario_to_toml(stated))
    assert "equipment" not in resolved["ecu"] and scenario_from_dict(resolved).equipment == "planar_steering"
