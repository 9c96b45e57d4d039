"""Plant FMU figures: the C model's cost per 1 ms internal step, and a 60 s run
through fmpy with 1 ms communication steps (FMU2Slave driven directly).

Goals (issue 3): <= 2 us per internal step; 60 s at 1 ms steps in <= 0.5 s wall.
Also prints the calibration figures: 0-100 km/h time, peak ABS deceleration on a
dry road, and the stopping distance from 100 km/h.

Run: python benchmarks/bench_fmu.py
"""

from __future__ import annotations

import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from fmu_plant.build import ensure_fmu

INTERNAL_STEP_S = 1e-3


def open_slave(fmu: str, params: dict[str, float]) -> tuple[FMU2Slave, dict[str, int]]:
    md = read_model_description(fmu)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu), modelIdentifier="vehicle_plant")
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    if params:
        slave.setReal([vrs[k] for k in params], list(params.values()))
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    return slave, vrs


def c_cost_per_step_us(fmu: str, inputs: dict[str, float], params: dict[str, float], sim_s: float) -> float:
    """One doStep over sim_s: the fmpy overhead is a single call, so this is the C cost."""
    slave, vrs = open_slave(fmu, params)
    slave.setReal([vrs[k] for k in inputs], list(inputs.values()))
    t0 = time.perf_counter()
    slave.doStep(0.0, sim_s)
    wall = time.perf_counter() - t0
    slave.terminate()
    slave.freeInstance()
    return wall / (sim_s / INTERNAL_STEP_S) * 1e6


def fmpy_loop_s(fmu: str, sim_s: float, with_io: bool) -> float:
    """sim_s at 1 ms communication steps; with_io also sets 2 inputs and reads 3 outputs per step."""
    slave, vrs = open_slave(fmu, {})
    inputs = [vrs["throttle"], vrs["brake"]]
    outputs = [vrs["x"], vrs["v"], vrs["wheel_speed_fl"]]
    n = int(round(sim_s / INTERNAL_STEP_S))
    t0 = time.perf_counter()
    for k in range(n):
        if with_io:
            slave.setReal(inputs, [1.0 if k < n // 2 else 0.0, 0.0 if k < n // 2 else 0.5])
        slave.doStep(k * INTERNAL_STEP_S, INTERNAL_STEP_S)
        if with_io:
            slave.getReal(outputs)
    wall = time.perf_counter() - t0
    slave.terminate()
    slave.freeInstance()
    return wall


def fmpy_raw_loop_s(fmu: str, sim_s: float) -> float:
    """As fmpy_loop_s with I/O, but through fmi2SetReal/fmi2GetReal with preallocated ctypes arrays."""
    import ctypes

    slave, vrs = open_slave(fmu, {})
    in_vr = (ctypes.c_uint * 2)(vrs["throttle"], vrs["brake"])
    in_val = (ctypes.c_double * 2)()
    out_vr = (ctypes.c_uint * 3)(vrs["x"], vrs["v"], vrs["wheel_speed_fl"])
    out_val = (ctypes.c_double * 3)()
    n = int(round(sim_s / INTERNAL_STEP_S))
    t0 = time.perf_counter()
    for k in range(n):
        in_val[0], in_val[1] = (1.0, 0.0) if k < n // 2 else (0.0, 0.5)
        slave.fmi2SetReal(slave.component, in_vr, 2, in_val)
        slave.fmi2DoStep(slave.component, k * INTERNAL_STEP_S, INTERNAL_STEP_S, 1)
        slave.fmi2GetReal(slave.component, out_vr, 3, out_val)
    wall = time.perf_counter() - t0
    slave.terminate()
    slave.freeInstance()
    return wall


def calibration(fmu: str) -> dict[str, float]:
    """0-100 km/h time, peak dry ABS deceleration (max 100 ms mean), stop from 100 km/h."""
    v100 = 100 / 3.6
    slave, vrs = open_slave(fmu, {})
    slave.setReal([vrs["throttle"]], [1.0])
    t100 = 0.0
    for k in range(15000):
        slave.doStep(k * INTERNAL_STEP_S, INTERNAL_STEP_S)
        if slave.getReal([vrs["v"]])[0] >= v100:
            t100 = (k + 1) * INTERNAL_STEP_S
            break
    slave.freeInstance()
    slave, vrs = open_slave(fmu, {"v0": v100})
    slave.setReal([vrs["brake"]], [1.0])
    decel, k = [], 0
    while True:
        slave.doStep(k * INTERNAL_STEP_S, INTERNAL_STEP_S)
        k += 1
        x, v, a = slave.getReal([vrs["x"], vrs["v"], vrs["a"]])
        decel.append(-a)
        if v <= 0.0:
            break
    slave.freeInstance()
    window = np.convolve(decel, np.ones(100) / 100, mode="valid")
    return {"t100_s": t100, "peak_decel_mps2": float(window.max()), "stop_m": x, "stop_s": k * INTERNAL_STEP_S}


def main() -> None:
    fmu = str(ensure_fmu(fmi_version=2))
    cases = {
        "full throttle from rest": ({"throttle": 1.0}, {}),
        "ABS braking from 100 km/h": ({"brake": 1.0}, {"v0": 100 / 3.6}),
    }
    for label, (inputs, params) in cases.items():
        best = min(c_cost_per_step_us(fmu, inputs, params, 60.0 if "throttle" in label else 3.0)
                   for _ in range(5))
        print(f"C model cost, {label}: {best:.3f} us per 1 ms internal step (goal <= 2 us)")
    for with_io, label in ((False, "doStep only"), (True, "doStep + setReal(2) + getReal(3)")):
        best = min(fmpy_loop_s(fmu, 60.0, with_io) for _ in range(3))
        print(f"60 s through fmpy at 1 ms steps, {label}: {best:.3f} s wall (goal <= 0.5 s)")
    best = min(fmpy_raw_loop_s(fmu, 60.0) for _ in range(3))
    print(f"60 s through fmpy at 1 ms steps, raw fmi2SetReal/DoStep/GetReal with ctypes arrays: "
          f"{best:.3f} s wall (goal <= 0.5 s)")
    cal = calibration(fmu)
    print(f"0-100 km/h: {cal['t100_s']:.2f} s; peak dry ABS deceleration (100 ms mean): "
          f"{cal['peak_decel_mps2']:.2f} m/s^2; stop from 100 km/h: {cal['stop_m']:.2f} m in {cal['stop_s']:.2f} s")


if __name__ == "__main__":
    main()
