"""Sub-stepping, FMI 2 vs FMI 3 and determinism: all compared bit for bit."""

import numpy as np
import pytest

from tests.fmu.plant_runner import OUTPUTS, run_plant


def dance(t: float) -> dict[str, float]:
    """Throttle, brake hard, a wet patch, release, throttle again; changes on a 50 ms grid."""
    if t < 3.0:
        return {"throttle": 1.0, "brake": 0.0, "road_friction": 1.0}
    if t < 4.5:
        return {"throttle": 0.0, "brake": 1.0, "road_friction": 1.0 if t < 4.0 else 0.6}
    if t < 5.0:
        return {"throttle": 0.0, "brake": 0.3, "road_friction": 0.6}
    return {"throttle": 0.6, "brake": 0.0, "road_friction": 1.0}


def assert_identical(a, b, stride_a=1, stride_b=1):
    np.testing.assert_allclose(a["t"][::stride_a], b["t"][::stride_b], rtol=0, atol=1e-12)
    for name in OUTPUTS:
        np.testing.assert_array_equal(a[name][::stride_a], b[name][::stride_b], err_msg=name)


def test_communication_step_does_not_change_the_trajectory(fmu2):
    runs = {h: run_plant(fmu2, 2, 6.0, h, dance) for h in (0.001, 0.01, 0.05)}
    assert runs[0.05]["v"].max() > 8.0  # the scenario really drives
    assert_identical(runs[0.001], runs[0.05], stride_a=50)
    assert_identical(runs[0.01], runs[0.05], stride_a=5)


def test_fmi2_and_fmi3_give_identical_trajectories(fmus):
    assert_identical(run_plant(fmus[2], 2, 6.0, 0.01, dance), run_plant(fmus[3], 3, 6.0, 0.01, dance))


@pytest.mark.parametrize("version", [2, 3])
def test_identical_inputs_give_bit_identical_outputs(fmus, version):
    assert_identical(run_plant(fmus[version], version, 6.0, 0.01, dance),
                     run_plant(fmus[version], version, 6.0, 0.01, dance))
