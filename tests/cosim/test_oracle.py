"""The offline oracle (cosim/matrix/oracle.py): what the true plant could have done from the radar's confirmation."""

from __future__ import annotations

import math

import pytest

from cosim.loop.experiment import resolve_fmu
from cosim.matrix import oracle
from cosim.matrix.catalogue import load_catalogue
from cosim.scenarios.loader import scenario_from_dict


def _cell(catalogue: str, cell_id: str):
    cell = next(c for c in load_catalogue(catalogue).cells if c.cell_id == cell_id)
    data = cell.scenario_dict()
    return data, resolve_fmu(scenario_from_dict(data))


def test_a_lane_change_is_one_lane_wide_in_the_kinematic_model_it_is_sized_with():
    m = oracle.Manoeuvre(100.0, math.radians(90.0))
    v, delta = 20.0, math.radians(90.0) / oracle.STEERING_RATIO
    t = m.pulse_s(v)
    # two pulses of T: yaw v delta T / L, lateral v^2 delta T^2 / L (small angles)
    assert v**2 * delta * t**2 / oracle.WHEELBASE_M == pytest.approx(oracle.LANE_WIDTH_M)
    assert oracle.Manoeuvre(100.0, 0.0).pulse_s(v) == math.inf
    assert oracle.GRID[0] == oracle.Manoeuvre(100.0, 0.0)  # braking straight is tried first
    assert len(set(oracle.GRID)) == len(oracle.GRID) == 1 + 3 * 12


def test_where_braking_is_too_late_and_the_next_lane_is_free_a_lane_change_avoids():
    data, fmu = _cell("emergency_steering", "cut-out-free-70")
    verdict = oracle.judge("cut-out-free-70", data, fmu)
    assert verdict.hit_object == "stopped car" and verdict.avoidable
    assert verdict.avoided_by is not None and verdict.avoided_by.wheel_offset_rad > 0.0  # to the free lane, left
    assert verdict.tried >= 2  # braking straight (the first) did not avoid
    # its confirmation: three 50 ms reports of the car, after it is uncovered (a time to it of 1.29 s, 70 km/h)
    assert 0.0 < verdict.confirmed_at_s < data["scenario"]["duration_s"]


def test_where_the_next_lane_is_occupied_nothing_of_the_grid_avoids():
    data, fmu = _cell("emergency_steering", "cut-out-occupied-70")
    verdict = oracle.judge("cut-out-occupied-70", data, fmu)
    assert verdict.hit_object == "stopped car" and verdict.confirmed_at_s is not None
    assert verdict.avoided_by is None and not verdict.avoidable and verdict.tried == len(oracle.GRID)


def test_a_cell_without_contact_has_nothing_to_avoid_and_the_ecu_is_not_heard(caplog):
    data, fmu = _cell("planar_false_positive", "kerb-stop-40")
    verdict = oracle.judge("kerb-stop-40", data, fmu)
    assert verdict == oracle.OracleVerdict("kerb-stop-40", None, None, None, 0) and verdict.avoidable
    # the baseline runs with the ECU disconnected: its gateway falls back to the driver at once
    assert any("driver commands only" in r.getMessage() for r in caplog.records)
