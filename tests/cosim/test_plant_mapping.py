"""FMU role mapping: errors list the FMU's variables of the right causality."""

import dataclasses

import pytest

from cosim.errors import MappingError, PlantError
from cosim.world.plant_fmu import FmuPlant
from cosim.scenarios.config import PlantConfig, SignalMap


def _with(plant_cfg, **roles):
    return dataclasses.replace(plant_cfg, **roles)


def test_missing_input_lists_fmu_inputs(plant_fmu3):
    cfg = _with(PlantConfig(), inputs=(SignalMap("throttle", ("gas",)), SignalMap("brake", ("brake",))))
    with pytest.raises(MappingError) as err:
        FmuPlant(cfg, plant_fmu3)
    msg = str(err.value)
    assert "plant.inputs.throttle" in msg and "'gas' is missing" in msg
    for name in ("brake", "grade", "road_friction", "throttle"):
        assert name in msg.split("inputs are:")[1]


def test_wrong_causality_lists_outputs(plant_fmu3):
    cfg = _with(PlantConfig(), outputs=(SignalMap("position", ("mass",)), SignalMap("speed", ("v",))))
    with pytest.raises(MappingError, match=r"'mass' is causality 'parameter'.*outputs are: a, ay, brake_pressure"):
        FmuPlant(cfg, plant_fmu3)


def test_unknown_parameter_and_missing_file(plant_fmu3, tmp_path):
    with pytest.raises(MappingError, match="plant.parameters.*'masss' is missing.*mass"):
        FmuPlant(PlantConfig(parameters={"masss": 1.0}), plant_fmu3)
    with pytest.raises(PlantError, match="not found"):
        FmuPlant(PlantConfig(), tmp_path / "none.fmu")
    broken = tmp_path / "broken.fmu"
    broken.write_bytes(b"not a zip")
    with pytest.raises(PlantError, match="not a readable FMU"):
        FmuPlant(PlantConfig(), broken)


def test_builtin_plant_reads_si_and_wheel_speeds(plant_fmu3):
    with FmuPlant(PlantConfig(parameters={"v0": 10.0}), plant_fmu3) as plant:
        s = plant.read()
        assert s.speed_mps == pytest.approx(10.0)
        assert s.wheel_speeds_mps == pytest.approx((10.0,) * 4, rel=0.01)
