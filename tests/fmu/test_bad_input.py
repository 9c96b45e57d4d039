"""Bad input: refused parameters, clamped or refused inputs, calls in the wrong state."""

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from tests.fmu.plant_runner import OUTPUTS, initialise, open_plant, run_plant

VERSIONS = [2, 3]
ERROR = 3


def closed(handle):
    handle.slave.freeInstance()


@pytest.mark.parametrize("version", VERSIONS)
@pytest.mark.parametrize("name, value", [("mass", -1500.0), ("mass", math.nan), ("wheel_radius", math.nan),
                                         ("brake_time_constant", -0.1), ("tyre_B", math.inf),
                                         ("brake_dead_time", 0.9), ("steering_ratio", 0.0),
                                         ("steering_time_constant", -0.1), ("yaw_inertia", math.nan),
                                         ("steering_angle_max", 2.0)])
def test_invalid_parameter_is_refused_at_initialisation(fmus, version, name, value):
    h = open_plant(fmus[version], version)
    try:
        with pytest.raises(FMICallException):
            initialise(h, {name: value})
        assert any(status == ERROR and f"'{name}'" in text for status, text in h.messages), h.log_text()
        with pytest.raises(FMICallException):  # still not initialised: no stepping
            h.slave.doStep(0.0, 0.01)
    finally:
        closed(h)


@pytest.mark.parametrize("version", VERSIONS)
def test_inconsistent_geometry_is_refused_naming_both_parameters(fmus, version):
    h = open_plant(fmus[version], version)
    try:
        with pytest.raises(FMICallException):
            initialise(h, {"cg_to_front_axle": 3.0})
        assert "'cg_to_front_axle'" in h.log_text() and "'wheelbase'" in h.log_text()
    finally:
        closed(h)


@pytest.mark.parametrize("version", VERSIONS)
def test_out_of_range_inputs_are_clamped_and_logged(fmus, version):
    over = run_plant(fmus[version], version, 2.0, 0.01, lambda t: {"throttle": 1.7, "brake": -0.5})
    full = run_plant(fmus[version], version, 2.0, 0.01, lambda t: {"throttle": 1.0, "brake": 0.0})
    for name in OUTPUTS:
        np.testing.assert_array_equal(over[name], full[name], err_msg=name)
    h = open_plant(fmus[version], version)
    try:
        initialise(h)
        h.set(throttle=1.7)
        h.set(throttle=1.7)  # logged once per excursion, not per call
        assert sum("'throttle'" in text and "clamped to 1" in text for _, text in h.messages) == 1
    finally:
        closed(h)


@pytest.mark.parametrize("version", VERSIONS)
def test_nan_input_is_an_error_and_never_reaches_the_outputs(fmus, version):
    h = open_plant(fmus[version], version)
    try:
        initialise(h, {"v0": 20.0})
        h.set(throttle=0.5)
        with pytest.raises(FMICallException):
            h.set(throttle=math.nan)
        assert "'throttle'" in h.log_text()
        h.slave.doStep(0.0, 0.1)
        values = h.get(*OUTPUTS)
        assert all(math.isfinite(v) for v in values)
        assert h.get("drive_force")[0] > 0.0  # the last valid throttle (0.5) still applies
    finally:
        closed(h)


@pytest.mark.parametrize("version", VERSIONS)
def test_steering_inputs_are_clamped_and_nan_is_refused(fmus, version):
    h = open_plant(fmus[version], version)
    try:
        initialise(h, {"v0": 10.0, "steering_time_constant": 0.0})
        h.set(steering_wheel_angle=25.0, steer_request=-3.0)
        assert "'steering_wheel_angle' = 25 is outside [-20, 20] rad: clamped to 20" in h.log_text()
        assert "'steer_request' = -3 is outside [-1.1, 1.1] rad: clamped to -1.1" in h.log_text()
        with pytest.raises(FMICallException):
            h.set(steer_request=math.nan)
        h.slave.doStep(0.0, 0.01)
        assert h.get("delta")[0] == pytest.approx(0.4 * 0.01)  # towards 20 / 16 - 1.1, at the rate limit
    finally:
        closed(h)


@pytest.mark.parametrize("version", VERSIONS)
def test_calls_in_the_wrong_state_return_an_error(fmus, version):
    h = open_plant(fmus[version], version)
    try:
        with pytest.raises(FMICallException):
            h.slave.doStep(0.0, 0.01)          # before initialisation
        with pytest.raises(FMICallException):
            h.get("v")                          # outputs not available yet
        with pytest.raises(FMICallException):
            h.slave.exitInitializationMode()    # never entered
        initialise(h)
        with pytest.raises(FMICallException):
            h.set(mass=1200.0)                  # fixed parameter after initialisation
        with pytest.raises(FMICallException):
            h.set(v=3.0)                        # an output
        with pytest.raises(FMICallException):
            h.slave.enterInitializationMode()   # already initialised
        with pytest.raises(FMICallException):
            h.slave.doStep(0.5, 0.01)           # not the current communication point
        with pytest.raises(FMICallException):
            h.slave.doStep(0.0, 0.0)            # not a positive step
        h.slave.doStep(0.0, 0.01)               # still alive and in step mode
        assert h.get("v") == [0.0]
        h.slave.terminate()
        with pytest.raises(FMICallException):
            h.slave.doStep(0.01, 0.01)          # after terminate
        assert "must not be called in state" in h.log_text()
    finally:
        closed(h)


def test_unknown_value_reference_is_an_error(fmu2):
    h = open_plant(fmu2, 2)
    try:
        initialise(h)
        with pytest.raises(FMICallException):
            h.slave.getReal([999])
        with pytest.raises(FMICallException):
            h.slave.getReal([h.vrs["abs_enabled"]])  # a Boolean read as Real
        assert "unknown value reference 999" in h.log_text()
    finally:
        closed(h)


def test_fmi3_refuses_model_exchange(fmus):
    from fmpy.fmi3 import FMU3Model

    from tests.fmu.plant_runner import _unpacked

    unzipdir, md = _unpacked(fmus[3])
    model = FMU3Model(guid=md.instantiationToken, unzipDirectory=unzipdir, modelIdentifier="vehicle_plant")
    messages = []
    with pytest.raises(Exception, match="Failed to instantiate"):
        model.instantiate(logMessage=lambda env, status, cat, msg: messages.append(msg.decode()))
    assert messages == ["model exchange is not supported"]
