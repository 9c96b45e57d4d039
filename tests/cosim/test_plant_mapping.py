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
    with pytest.raises(MappingError, match=r"'mass' is causality 'parameter'.*outputs are: a, ax, ay, brake_pressure"):
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


def _planar_cfg(**kw) -> PlantConfig:
    """The builtin plant with its planar inputs and outputs mapped, as the loader maps them for a planar run."""
    from cosim.scenarios.config import BUILTIN_PLANAR_INPUTS, BUILTIN_PLANAR_OUTPUTS

    cfg = PlantConfig(parameters={"v0": 15.0, "steering_time_constant": 0.0})
    maps = {"inputs": cfg.inputs + BUILTIN_PLANAR_INPUTS, "outputs": cfg.outputs + BUILTIN_PLANAR_OUTPUTS}
    return _with(cfg, **{**maps, **kw})


def _steered(plant: FmuPlant, overlay_rad: float, cycles: int = 100) -> float:
    """Drive 1 s with the driver's wheel straight and ``overlay_rad`` as the ECU's request; the road-wheel angle."""
    for k in range(cycles):
        plant.set_actuation(0.2, 0.0, 0.0, overlay_rad)
        plant.step(k * 0.01, 0.01)
    return plant._fmu.getFloat64([25])[0]  # vr 25: the road-wheel angle delta


def test_steer_request_role_moves_the_road_wheel_and_is_optional(plant_fmu3):
    with FmuPlant(_planar_cfg(), plant_fmu3) as plant:
        assert _steered(plant, 0.02) == pytest.approx(0.02, rel=1e-9)
        assert plant.read().yaw_rad > 0.0  # turning left
    without = tuple(m for m in _planar_cfg().inputs if m.role != "steer_request")
    with FmuPlant(_planar_cfg(inputs=without), plant_fmu3) as plant:  # a plant without the input: ignored
        assert _steered(plant, 0.02) == 0.0 and plant.read().yaw_rad == 0.0


def test_sample_has_the_plants_ax_ay_or_their_fallbacks(plant_fmu3):
    with FmuPlant(_planar_cfg(), plant_fmu3) as plant:
        _steered(plant, 0.03)
        s = plant.read()
        ay, ax = plant._fmu.getFloat64([22, 26])  # the FMU's ay and ax outputs
        assert (s.ay_mps2, s.ax_mps2) == (ay, ax) and ay > 1.0
        assert s.ay_mps2 != s.vx_mps * s.yaw_rate_radps  # the plant's own, not the steady-state estimate
    pose_only = tuple(m for m in _planar_cfg().outputs if m.role not in ("ax", "ay"))
    with FmuPlant(_planar_cfg(outputs=pose_only), plant_fmu3) as plant:  # a plant without them
        _steered(plant, 0.03)
        s = plant.read()
        assert s.ay_mps2 == s.vx_mps * s.yaw_rate_radps and s.ax_mps2 == s.accel_mps2
    with FmuPlant(PlantConfig(parameters={"v0": 15.0}), plant_fmu3) as plant:  # a 1-D plant: ESC as before
        s = plant.read()
        assert (s.ay_mps2, s.ax_mps2, s.yaw_rate_radps) == (0.0, s.accel_mps2, 0.0)
