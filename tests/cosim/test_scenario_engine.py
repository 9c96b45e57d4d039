"""The scenario engine in closed loop: initial speed for any plant, the PI robot driver, lateral overlap, braking targets."""

import pytest

from cosim.loop.master import run_scenario
from cosim.scenarios.config import DriverConfig
from cosim.scenarios.loader import scenario_from_dict
from cosim.world.driver_models import cruise, hold_speed

from .test_closed_loop import FIXTURE_PLANT

CAR = {"length_m": 4.023, "width_m": 1.712}


def _toy_plant(model, seconds=30.0, v0=20.0, set_mps=20.0):
    """First-order car: a = 3 m/s^2 * pedal - 0.4 m/s^2 road load; pedal from the driver every 10 ms."""
    v = v0
    for k in range(int(seconds / 0.01)):
        pedals = model(k * 0.01, 0.0, v)
        v += (3.0 * pedals.accel_pct / 100.0 - 0.4 - 3.0 * pedals.brake_pct / 100.0) * 0.01
    return v - set_mps


def test_pi_robot_holds_speed_without_steady_state_error_where_p_does_not():
    cfg = DriverConfig(model="hold_speed", set_speed_mps=20.0)
    assert abs(_toy_plant(hold_speed(cfg))) < 0.01
    assert _toy_plant(cruise(DriverConfig(model="cruise", set_speed_mps=20.0))) < -0.05  # P law: 0.067 m/s short


def test_robot_never_brakes_and_releases_after_the_drop():
    model = hold_speed(DriverConfig(model="hold_speed", set_speed_mps=20.0, release_drop_mps=5 / 3.6))
    assert model(0.0, 0.0, 25.0).brake_pct == 0.0  # too fast: lifts off, never brakes
    assert model(0.1, 0.0, 19.0).accel_pct > 0.0
    assert model(0.2, 0.0, 18.5).accel_pct == 0.0  # 1.5 m/s below: released ...
    assert model(0.3, 0.0, 15.0).accel_pct == 0.0 and model(0.4, 0.0, 20.0).accel_pct == 0.0  # ... for good


def _robot(speed_mps, **extra):
    return {"model": "hold_speed", "set_speed_mps": speed_mps, **extra}


@pytest.mark.slow
def test_builtin_plant_starts_at_speed_and_robot_holds_it(plant_fmu3):
    sc = scenario_from_dict({"scenario": {"duration_s": 10.0}, "plant": {"initial_speed_mps": 13.89},
                             "driver": _robot(13.89), "object": {"enabled": False}})
    rec = run_scenario(sc, plant_fmu3, "tightening")
    speeds = rec.column("speed_mps")
    assert speeds[0] == pytest.approx(13.89)
    assert abs(sum(speeds[-100:]) / 100 - 13.89) < 0.02  # last second: no steady-state error
    assert min(speeds) > 13.89 - 0.3  # start-up (ECU FAULT, drive lag) costs little


def test_mapped_fmu_starts_at_speed_through_its_declared_parameter(point_mass_fmu):
    plant = dict(FIXTURE_PLANT, fmu=str(point_mass_fmu), initial_speed_mps=10.0,
                 initial={"speed": {"name": "v_start_kmh", "scale": 3.6}})
    sc = scenario_from_dict({"scenario": {"duration_s": 0.5}, "plant": plant, "driver": _robot(10.0),
                             "object": {"enabled": False}})
    rec = run_scenario(sc, point_mass_fmu, "none")
    assert rec.column("speed_mps")[0] == pytest.approx(10.0)


@pytest.mark.slow
@pytest.mark.parametrize("strategy", ["none", "tightening"])
def test_car_in_the_adjacent_lane_is_passed_not_hit(plant_fmu3, strategy):
    sc = scenario_from_dict({"scenario": {"duration_s": 7.0}, "plant": {"initial_speed_mps": 13.89},
                             "driver": _robot(13.89), "objects": [dict(position_m=60.0, lateral_m=3.5, **CAR)]})
    rec = run_scenario(sc, plant_fmu3, strategy)
    assert not rec.metrics.collided
    assert rec.column("position_m")[-1] > 70.0  # drove past it
    assert set(rec.column("ecu_mode")[20:]) == {"STANDBY"}  # the ECU never reacted


@pytest.mark.slow
def test_braking_target_is_hit_when_the_ecu_is_blind(plant_fmu3):
    """CCRb shape: a car 1 s ahead at 50 km/h brakes at 4 m/s^2 (reached in 1 s) from t = 1 s to a stop.

    With the radar blind (every update dropped) the robot keeps 50 km/h: contact when the target
    has lost the 13.89 m gap, D R^2/6 + 2u + 2u^2 = 13.89 (u after the 1 s ramp) -> u = 2.12 s,
    t = 4.12 s, relative speed 2 + 4u = 10.48 m/s.
    """
    target = dict(position_m=13.89, speed_mps=13.89, brake_decel_mps2=4.0, brake_ramp_s=1.0, brake_at_s=1.0, **CAR)
    data = {"scenario": {"duration_s": 8.0}, "plant": {"initial_speed_mps": 13.89}, "driver": _robot(13.89),
            "objects": [target], "radar": {"dropout_probability": 1.0}}
    rec = run_scenario(scenario_from_dict(data), plant_fmu3, "none")
    hit = [e for e in rec.events if e.kind == "collision"]
    assert rec.metrics.collided and hit[0].t_s == pytest.approx(4.12, abs=0.05)
    assert rec.metrics.impact_speed_mps == pytest.approx(10.48, abs=0.25)
