"""``[plant] isolation = "process"``: a native fault in the FMU becomes an error naming the time and cause.

Each case runs the closed loop on the faulty fixture FMU (pythonfmu) with a
fault from t = 1 s, and checks that the run stops there with the results so
far, and that no child process is left behind.
"""

from __future__ import annotations

import time

import pytest

from cosim.loop.master import ClosedLoop
from cosim.scenarios.loader import scenario_from_dict
from cosim.world.plant_process import IsolatedPlant
from tests.os_processes import process_gone


def _scenario(fault: int, isolation: str = "process", timeout_s: float = 1.0):
    return scenario_from_dict({
        "scenario": {"duration_s": 3.0, "step_s": 0.01},
        "plant": {"fmu": "faulty.fmu", "isolation": isolation, "step_timeout_s": timeout_s,
                  "parameters": {"fault": fault, "fault_at": 1.0},
                  "inputs": {"accel_command": {"name": "a_cmd"}},
                  "outputs": {"position": {"name": "s_m"}, "speed": {"name": "v_mps"}}},
        "object": {"position_m": 500.0},
        "driver": {"model": "full_throttle"},
    })


def _run(faulty_fmu, fault: int, **kw):
    loop = ClosedLoop(_scenario(fault, **kw), faulty_fmu, "tightening")
    pid = loop.plant.pid
    t0 = time.monotonic()
    record = loop.run()
    return record, pid, time.monotonic() - t0


@pytest.mark.parametrize("fault, cause", [(1, "SIGABRT"), (2, "SIGSEGV")])
def test_a_crash_in_dostep_stops_the_run_with_time_and_cause(faulty_fmu, fault, cause):
    record, pid, _ = _run(faulty_fmu, fault)
    assert record.error is not None and cause in record.error and "t = 1.0" in record.error
    assert record.metrics.sim_time_s == pytest.approx(1.0, abs=0.011)
    assert len(record.rows) >= 99  # the results up to the crash are kept
    assert any(e.kind == "fmi_error" for e in record.events)
    assert process_gone(pid)


def test_a_hang_in_dostep_is_detected_within_the_timeout(faulty_fmu):
    record, pid, wall_s = _run(faulty_fmu, 3, timeout_s=0.5)
    assert record.error is not None and "hung" in record.error and "t = 1.0" in record.error
    assert wall_s < 0.5 + 1.0 + 3.0  # timeout + 1 s, plus the child's start-up and the 1 s of driving
    assert process_gone(pid)


def test_nan_output_names_the_time_and_the_variable(faulty_fmu):
    record, pid, _ = _run(faulty_fmu, 4)
    assert record.error is not None and "'v_mps'" in record.error and "nan" in record.error
    assert "t = 1.0" in record.error
    assert process_gone(pid)


def test_a_hang_in_terminate_does_not_lose_a_finished_run(faulty_fmu):
    record, pid, wall_s = _run(faulty_fmu, 5, timeout_s=0.5)
    assert record.error is None
    assert record.metrics.sim_time_s == pytest.approx(3.0)
    assert process_gone(pid)


def test_auto_isolates_third_party_fmus_only(faulty_fmu):
    loop = ClosedLoop(_scenario(0, isolation="auto"), faulty_fmu, "tightening")
    try:
        assert isinstance(loop.plant, IsolatedPlant)
    finally:
        loop.close()
