"""A third-party planar vehicle through ``[plant]`` mapping (issue 22, item 4): CommonRoad's ST model
(vehicle 2, as the package ships it) packaged as an FMU with pythonfmu (``st_vehicle_slave.py``), driving a
bundled planar scene and the whole planar false-positive catalogue."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest

from cosim.errors import ConfigError
from cosim.loop.master import ClosedLoop
from cosim.matrix.catalogue import bundled, load_catalogue
from cosim.matrix.runner import run_matrix
from cosim.scenarios.loader import scenario_from_dict

SCENARIOS = Path(__file__).resolve().parents[2] / "cosim" / "scenarios"

#: CommonRoad vehicle 2 (BMW 320i): body 4.508 x 1.61 m, a = 1.156 m and b = 1.423 m from the CG to the axles
#: (vehiclemodels.parameters_vehicle2); the ST model's pose is its centre of gravity, the box centred on it
ST_PLANT = {
    "length_m": 4.508, "width_m": 1.61,
    "inputs": {"accel_command": "a_cmd", "steering_wheel_angle": {"name": "delta_cmd", "scale": 1.0 / 16.0},
               "steer_request": "delta_overlay", "road_friction": "mu"},
    "outputs": {"position": "x", "speed": "v_lon", "accel": "a_lon", "y": "y", "yaw": "psi",
                "yaw_rate": "psi_dot", "vx": "v_lon", "vy": "v_lat"},
    "initial": {"speed": "v_start", "y": "y_start", "yaw": "psi_start"},
}
#: the path-following driver's model of that car (its steering ratio: the fixture's 1/16 input scale)
ST_GEOMETRY = {"wheelbase_m": 2.578912, "cg_to_rear_axle_m": 1.4227170936, "steering_ratio": 16.0,
               "max_road_wheel_angle_rad": 1.066}


def _on_st(data: dict, fmu: Path) -> dict:
    data = copy.deepcopy(data)
    data["plant"] = {**data.get("plant", {}), **ST_PLANT, "fmu": str(fmu)}
    data["driver"]["steering"].update(ST_GEOMETRY)
    return data


def test_the_st_vehicle_changes_lane_past_the_parked_car_and_back(st_vehicle_fmu):
    data = tomllib.loads((SCENARIOS / "lane_change_parked_car.toml").read_text())
    record = ClosedLoop(scenario_from_dict(_on_st(data, st_vehicle_fmu)), st_vehicle_fmu, "tightening").run()
    assert record.error is None and not record.metrics.collided
    columns = list(record.columns)
    y = np.array([row[columns.index("y_m")] for row in record.rows])
    speed = np.array([row[columns.index("speed_mps")] for row in record.rows])
    assert 3.2 < y.max() < 3.8  # the left lane's centre, 3.5 m over
    assert abs(y[-1]) < 0.3 and abs(y[: len(y) // 6]).max() < 0.05  # back in its lane; straight before
    assert abs(speed - 13.89).max() < 0.2  # the robot's pedal holds 50 km/h through both changes


def _catalogue_on_st(tmp_path: Path, fmu: Path, geometry: dict) -> Path:
    """The bundled planar false-positive catalogue with ``[scenario.plant]`` the ST vehicle's mapping."""
    head, series = bundled()["planar_false_positive"].read_text().split("[[series]]", 1)
    scalars = "\n".join(f"{k} = {v!r}" for k, v in ST_PLANT.items() if not isinstance(v, dict))
    tables = "".join(f"\n[scenario.plant.{table}]\n" + "\n".join(
        f"{role} = {_toml(spec)}" for role, spec in ST_PLANT[table].items()) for table in ("inputs", "outputs", "initial"))
    steering = "\n".join(f"{k} = {v!r}" for k, v in geometry.items())
    catalogue = tmp_path / "planar_false_positive_st.toml"
    catalogue.write_text(f"{head}\n[scenario.plant]\nfmu = {str(fmu)!r}\n{scalars}\n{tables}\n\n"
                         f"[scenario.driver.steering]\nmodel = 'path_following'\n{steering}\n\n[[series]]{series}")
    return catalogue


def test_the_planar_false_positive_catalogue_runs_on_the_st_vehicle(st_vehicle_fmu, tmp_path):
    cat = load_catalogue(_catalogue_on_st(tmp_path, st_vehicle_fmu, ST_GEOMETRY))
    rows, _ = run_matrix([cat], ["tightening"], phases=1, workers=2)
    assert len(rows) == len(load_catalogue("planar_false_positive").cells) == 12
    durations = {c.cell_id: c.scenario_dict()["scenario"]["duration_s"] for c in cat.cells}
    for row in rows:
        assert row["error"] is None, (row["cell"], row["error"])
        assert not row["collided"] and row["road_departure_m"] == 0.0, row["cell"]
        # run to its end: the whole duration (to the cycle), or the end condition it declares (a stop)
        assert row["end_reason"] is not None or abs(row["sim_time_s"] - durations[row["cell"]]) < 0.0101, row


def test_a_catalogue_missing_the_third_party_geometry_names_the_key_and_the_file(st_vehicle_fmu, tmp_path):
    without_ratio = {k: v for k, v in ST_GEOMETRY.items() if k != "steering_ratio"}
    catalogue = _catalogue_on_st(tmp_path, st_vehicle_fmu, without_ratio)
    with pytest.raises(ConfigError) as err:
        load_catalogue(catalogue)
    message = str(err.value)
    assert "\n" not in message and message.startswith(f"{catalogue}: scenario.driver.steering.steering_ratio: ")


def _toml(spec) -> str:
    if isinstance(spec, dict):
        return "{" + ", ".join(f"{k} = {v!r}" for k, v in spec.items()) + "}"
    return repr(spec)
