"""Any communication step: whole multiples of 1 ms reproduce the 1 ms-only plant bit for
bit; other steps end with a shorter sub-step and stay within a stated tolerance of it.

The reference is the trajectory of the plant before it took other steps
(``tests/fmu/data/dance_reference.json``, see ``reference_trajectory.py``).
"""

import fmpy
import numpy as np
import pytest

from tests.fmu.plant_runner import OUTPUTS, run_plant
from tests.fmu.reference_trajectory import STOP_S, load_reference
from tests.fmu.test_integration import dance

#: largest difference from the 1 ms trajectory at the 50 ms points, for steps whose
#: sub-steps are shorter than 1 ms (fmu_plant/README.md, "Communication steps").
#: Wheel speeds differ most: under ABS the wheels cycle, and a shorter sub-step shifts
#: the phase of that cycle; the body's speed and position hardly move.
TOLERANCE = {"x": 0.01, "v": 0.02, "a": 0.1, "wheel_speed_fl": 1.0, "wheel_speed_fr": 1.0,
             "wheel_speed_rl": 1.0, "wheel_speed_rr": 1.0, "brake_pressure": 1e-6,
             "drive_force": 1e-6}


def at_reference_points(run, ref, step_s):
    return [int(round(t / step_s)) for t in ref["t"]]


@pytest.mark.parametrize(("version", "step_s"), [(2, 0.001), (2, 0.01), (2, 0.05), (3, 0.01)])
def test_whole_multiples_of_1ms_reproduce_the_reference_bit_for_bit(fmus, version, step_s):
    ref = load_reference()
    run = run_plant(fmus[version], version, STOP_S, step_s, dance)
    idx = at_reference_points(run, ref, step_s)
    for name in OUTPUTS:
        np.testing.assert_array_equal(run[name][idx], ref[name], err_msg=name)


@pytest.mark.parametrize(("version", "step_s"), [(2, 0.0025), (2, 0.0005), (3, 0.0025)])
def test_steps_that_split_the_1ms_grid_stay_within_tolerance(fmus, version, step_s):
    ref = load_reference()
    run = run_plant(fmus[version], version, STOP_S, step_s, dance)
    idx = at_reference_points(run, ref, step_s)
    assert run["t"][-1] == pytest.approx(STOP_S, abs=1e-9)
    assert ref["v"].max() > 8.0 and ref["x"][-1] > 20.0  # the scenario really drives and brakes
    for name in OUTPUTS:
        worst = np.max(np.abs(run[name][idx] - ref[name]))
        assert worst <= TOLERANCE[name], f"{name}: {worst} > {TOLERANCE[name]}"


@pytest.mark.parametrize("version", [2, 3])
def test_fmpy_simulate_fmu_with_a_2_5ms_output_interval(fmus, version):
    """The interval of finding 1, which the 1 ms-only plant refused ("not a positive multiple")."""
    result = fmpy.simulate_fmu(str(fmus[version]), stop_time=1.0, output_interval=0.0025,
                               start_values={"throttle": 1.0}, output=["x", "v"])
    assert result["time"][-1] == pytest.approx(1.0)
    assert len(result) == 401
    one_ms = fmpy.simulate_fmu(str(fmus[version]), stop_time=1.0, output_interval=0.001,
                               start_values={"throttle": 1.0}, output=["x", "v"])
    np.testing.assert_allclose(result["v"][::2], one_ms["v"][::5], rtol=0, atol=TOLERANCE["v"])
    assert result["v"][-1] > 1.0


def test_fmi2_declares_that_it_takes_any_step(fmus):
    md2 = fmpy.read_model_description(str(fmus[2]))
    md3 = fmpy.read_model_description(str(fmus[3]))
    assert md2.coSimulation.canHandleVariableCommunicationStepSize is True
    assert md3.coSimulation.canHandleVariableCommunicationStepSize is True
    assert float(md3.coSimulation.fixedInternalStepSize) == 0.001


def test_a_step_resumes_inside_a_grid_cell_and_a_step_below_the_resolution_is_refused(fmu2):
    from fmpy.fmi1 import FMICallException

    from tests.fmu.plant_runner import initialise, open_plant

    h = open_plant(fmu2, 2)
    try:
        initialise(h)
        h.set(throttle=1.0)
        h.slave.doStep(0.0, 0.0015)            # ends half-way through the second 1 ms cell
        h.slave.doStep(0.0015, 0.0085)         # completes it, then whole steps to 10 ms
        with pytest.raises(FMICallException):
            h.slave.doStep(0.01, 1e-13)        # below the 1 ns time resolution
        assert "below the 1e-09 s time resolution" in h.log_text()
        v_split = h.get("v")[0]
    finally:
        h.slave.terminate()
        h.slave.freeInstance()
    whole = run_plant(fmu2, 2, 0.01, 0.01, lambda t: {"throttle": 1.0})
    assert v_split == pytest.approx(whole["v"][-1], abs=1e-6) and v_split > 0.0
