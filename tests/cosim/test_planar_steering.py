"""Steering avoids what braking cannot (issue 22), in the closed loop, and only with steering authority.

The emergency-steering catalogue's late stationary car at 80 km/h on a two-lane road, the lane to the
left free, here standing 1.4 m right of our lane's centre (its left side 0.5 m right of ours: it
overlaps the right of our path by 0.37 m). Uncovered 33.3 m ahead, it is beyond braking alone (0.35 s
and 8.9 m/s^2 need 35.5 m). With the builtin planar plant (its ``steer_request`` input mapped: steering
authority) the ECU's region finds a steering path whose stopping path is disjoint (``STEER_AND_BRAKE``),
the EPS applies its SteeringOverride, and the car stops beside the stopped car, on the road. The same
scene with the plant's ``steer_request`` unmapped (no authority) brakes only: the ECU never sends
SteerActive 1, and the car hits the stopped one. Two runs of about 7 s simulated.
"""

import dataclasses

import pytest

from can_dbc import LAYOUTS, check_alone
from cosim.loop.master import ClosedLoop, ecu_config
from cosim.matrix.catalogue import load_catalogue
from cosim.scenarios.loader import scenario_from_dict

CELL = "late-stationary-free-80"
LATERAL_M = -1.4
STEERING_ID = LAYOUTS["SteeringOverride"].frame_id
ROAD_LEFT_EDGE_M = 1.75 + 3.5  # the catalogue's road: reference line at y = 1.75, one 3.5 m lane each way
EGO_HALF_WIDTH_M = 1.815 / 2


@pytest.fixture(scope="module")
def fmu():
    from fmu_plant.build import ensure_fmu

    return ensure_fmu(fmi_version=3)


def scenario(authority: bool):
    cell = next(c for c in load_catalogue("emergency_steering").cells if c.cell_id == CELL)
    data = cell.scenario_dict()
    assert data["objects"][0]["name"] == "stopped car"
    data["objects"][0]["lateral_m"] = LATERAL_M
    sc = scenario_from_dict(data)
    if not authority:
        inputs = tuple(m for m in sc.plant.inputs if m.role != "steer_request")
        sc = dataclasses.replace(sc, plant=dataclasses.replace(sc.plant, inputs=inputs))
    return sc


def steer_active_frames(record) -> int:
    return sum(1 for f in record.frames if f.arbitration_id == STEERING_ID
               and check_alone(_msg(f)).signals["SteerActive"] == 1)


def _msg(frame):
    import can

    return can.Message(arbitration_id=frame.arbitration_id, data=frame.data, is_extended_id=False)


def test_authority_is_the_plants_steering_input():
    assert ecu_config(scenario(True), "tightening").steering_authority
    assert not ecu_config(scenario(False), "tightening").steering_authority


@pytest.mark.slow
def test_steering_avoids_what_braking_cannot_and_only_with_authority(fmu):
    steered = ClosedLoop(scenario(True), fmu, "tightening").run()
    col = {c: i for i, c in enumerate(steered.columns)}
    last = steered.rows[-1]
    assert not steered.metrics.collided and steer_active_frames(steered) > 0
    assert last[col["speed_mps"]] < 0.5  # stopped beside it, along the steering path
    assert 1.0 < last[col["y_m"]] and last[col["y_m"]] + EGO_HALF_WIDTH_M < ROAD_LEFT_EDGE_M  # on the road
    assert 2.0 in {row[col["region_contingency"]] for row in steered.rows}  # STEER_AND_BRAKE reported

    braked = ClosedLoop(scenario(False), fmu, "tightening").run()
    assert braked.metrics.collided and braked.contact["object"] == 0 and steer_active_frames(braked) == 0
    col = {c: i for i, c in enumerate(braked.columns)}
    assert 2.0 not in {row[col["region_contingency"]] for row in braked.rows}  # no steering row without authority
    assert all(row[col["steer_overlay_rad"]] == 0.0 and row[col["y_m"]] == 0.0 for row in braked.rows)


def test_the_birdseye_draws_the_reported_stopping_path():
    """The region columns become a band of the ego's width along the reported arc, labelled with the contingency;
    NOT_EVALUATED and rows before the first report draw nothing; a report held over several rows is drawn at each
    of them, from the car's pose there (the band moves with the car)."""
    import numpy as np

    from cosim.results.region_view import regions_from_columns, stopping_band
    from cosim.results.scene_file import Body

    body = Body("ego", "ego", 4.0, 2.0, 2.0)
    cols = {"region_contingency": ["nan", "4", "0", "0", "2"], "region_curvature_1pm": ["nan", "0", "0", "0", "0.1"],
            "region_stopping_m": ["nan", "0", "10", "10", "5"]}
    t_s, pose = np.arange(5) * 0.1, np.zeros((5, 3))
    pose[3, 0] = 1.5  # the car has moved on while the report is held
    times, polygons, labels = regions_from_columns(cols, t_s, pose, body)
    assert list(times) == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])
    assert labels == ("", "", "DRIVER_PATH", "DRIVER_PATH", "STEER_AND_BRAKE")
    assert len(polygons[0]) == len(polygons[1]) == 0
    assert polygons[3][:, 0] - polygons[2][:, 0] == pytest.approx(np.full(len(polygons[2]), 1.5))
    straight = polygons[2]
    assert straight[:, 0].min() == pytest.approx(2.0) and straight[:, 0].max() == pytest.approx(12.0)  # from the front
    assert straight[:, 1].min() == pytest.approx(-1.0) and straight[:, 1].max() == pytest.approx(1.0)
    arc = stopping_band((0.0, 0.0, 0.0), body, 0.1, 5.0)
    assert arc[16, 1] > 0.9 and arc[16, 0] == pytest.approx(2.0 + 10.0 * np.sin(0.5) - 1.0 * np.sin(0.5))
    assert regions_from_columns({}, t_s, pose, body) is None
