"""Plant FMU figures: the C model's cost per 1 ms internal step, and a 60 s run
through fmpy with 1 ms communication steps (FMU2Slave driven directly).

Goals (issue 3): <= 2 us per internal step; 60 s at 1 ms steps in <= 0.5 s wall.
Also prints the calibration figures: 0-100 km/h time, peak ABS deceleration on a
dry road, and the stopping distance from 100 km/h.

Issue 21, the planar plant against today's (``--baseline-rev``, default d2cf42d, the last
longitudinal-only plant, built from that commit's ``fmu_plant/`` with its own build script):
side by side, alternating, ``--rounds`` rounds, medians and the median of the per-round
ratios. Goal: the planar plant costs at most 1.3x today's per step with fmpy stepping it
alone. Both get the same throttle / brake inputs; the planar plant also gets a steering-wheel
angle (a 0.5 Hz sine), so its lateral equations really run; "straight" rows hold it at 0.

Times are this process's CPU time (``time.process_time``): the machine is shared, and CPU
time does not count the time other processes hold the core.

Run: python benchmarks/bench_fmu.py [--rounds N] [--baseline-rev REV] [--skip-calibration]
"""

from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from fmu_plant.build import DEFAULT_CACHE_DIR, ensure_fmu

INTERNAL_STEP_S = 1e-3
REPO = Path(__file__).resolve().parent.parent
BASELINE_REV = "d2cf42d"


def baseline_fmu(rev: str) -> str:
    """Today's plant: ``fmu_plant/`` of git ``rev`` built with its own build script (cached)."""
    sha = subprocess.run(["git", "-C", str(REPO), "rev-parse", rev], capture_output=True, text=True,
                         check=True).stdout.strip()
    out = DEFAULT_CACHE_DIR / f"baseline-{sha[:12]}" / "vehicle_plant.fmu"
    if out.is_file():
        return str(out)
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", str(REPO), "archive", sha, "fmu_plant"], capture_output=True,
                                 check=True).stdout
        with tarfile.open(fileobj=__import__("io").BytesIO(archive)) as tar:
            tar.extractall(tmp, filter="data")
        code = "import sys; from fmu_plant.build import build_fmu; build_fmu(2, sys.argv[1])"
        subprocess.run([sys.executable, "-c", code, str(out)], cwd=tmp, check=True)
    return str(out)


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
    t0 = time.process_time()
    slave.doStep(0.0, sim_s)
    wall = time.process_time() - t0
    slave.terminate()
    slave.freeInstance()
    return wall / (sim_s / INTERNAL_STEP_S) * 1e6


def fmpy_loop_s(fmu: str, sim_s: float, with_io: bool, steer_rad: float = 0.0, step_s: float = INTERNAL_STEP_S,
                ) -> float:
    """sim_s at ``step_s`` communication steps; with_io also sets 2 inputs and reads 3 outputs per step.
    ``steer_rad`` > 0 (planar plant only): also sets a steering-wheel angle of that amplitude, 0.5 Hz."""
    slave, vrs = open_slave(fmu, {"v0": 15.0})
    inputs = [vrs["throttle"], vrs["brake"]] + ([vrs["steering_wheel_angle"]] if steer_rad else [])
    outputs = [vrs["x"], vrs["v"], vrs["wheel_speed_fl"]]
    n = int(round(sim_s / step_s))
    if not with_io and steer_rad:
        slave.setReal([vrs["steering_wheel_angle"]], [steer_rad])
    t0 = time.process_time()
    for k in range(n):
        if with_io:
            pedals = [0.3, 0.0] if k < n // 2 else [0.0, 0.3]
            steer = [steer_rad * math.sin(math.pi * k * step_s)] if steer_rad else []
            slave.setReal(inputs, pedals + steer)
        slave.doStep(k * step_s, step_s)
        if with_io:
            slave.getReal(outputs)
    wall = time.process_time() - t0
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
    t0 = time.process_time()
    for k in range(n):
        in_val[0], in_val[1] = (1.0, 0.0) if k < n // 2 else (0.0, 0.5)
        slave.fmi2SetReal(slave.component, in_vr, 2, in_val)
        slave.fmi2DoStep(slave.component, k * INTERNAL_STEP_S, INTERNAL_STEP_S, 1)
        slave.fmi2GetReal(slave.component, out_vr, 3, out_val)
    wall = time.process_time() - t0
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


#: side-by-side cases: label -> (function of (fmu, steer_rad), unit)
STEER_RAD = 1.6  # steering-wheel amplitude: 0.1 rad at the road wheel, about 0.4 g at 15 m/s


def _cases() -> dict[str, tuple]:
    return {
        "C model, one doStep over 20 s (us per 1 ms step)": (
            lambda fmu, steer: c_cost_per_step_us(fmu, {"throttle": 0.3, **({"steering_wheel_angle": steer}
                                                                              if steer else {})}, {"v0": 15.0}, 20.0),
            "us"),
        "fmpy doStep 1 ms only (us per step)": (
            lambda fmu, steer: fmpy_loop_s(fmu, 10.0, False, steer) / 10_000 * 1e6, "us"),
        "fmpy setReal + doStep 1 ms + getReal(3) (us per step)": (
            lambda fmu, steer: fmpy_loop_s(fmu, 10.0, True, steer) / 10_000 * 1e6, "us"),
        "fmpy doStep 10 ms only, the co-simulation cycle (us per step)": (
            lambda fmu, steer: fmpy_loop_s(fmu, 20.0, False, steer, 0.01) / 2_000 * 1e6, "us"),
        "fmpy setReal + doStep 10 ms + getReal(3) (us per step)": (
            lambda fmu, steer: fmpy_loop_s(fmu, 20.0, True, steer, 0.01) / 2_000 * 1e6, "us"),
    }


def side_by_side(base: str, planar: str, rounds: int) -> None:
    """Today's plant and the planar one (steering and straight), alternating; medians and ratios."""
    for label, (measure, unit) in _cases().items():
        rows: dict[str, list[float]] = {"today": [], "planar, steering": [], "planar, straight": []}
        for _ in range(rounds):
            rows["today"].append(measure(base, 0.0))
            rows["planar, steering"].append(measure(planar, STEER_RAD))
            rows["planar, straight"].append(measure(planar, 0.0))
        print(f"{label}:")
        for name, values in rows.items():
            line = f"  {name:18s} median {statistics.median(values):8.3f} {unit}"
            if name != "today":
                ratios = [a / b for a, b in zip(values, rows["today"])]
                line += (f"   ratio to today: median {statistics.median(ratios):.3f}"
                         f" (min {min(ratios):.3f}, max {max(ratios):.3f})")
            print(line)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--baseline-rev", default=BASELINE_REV)
    parser.add_argument("--skip-calibration", action="store_true")
    args = parser.parse_args(argv)
    fmu = str(ensure_fmu(fmi_version=2))
    side_by_side(baseline_fmu(args.baseline_rev), fmu, args.rounds)
    if args.skip_calibration:
        return
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
        print(f"60 s through fmpy at 1 ms steps, {label}: {best:.3f} s CPU (goal <= 0.5 s)")
    best = min(fmpy_raw_loop_s(fmu, 60.0) for _ in range(3))
    print(f"60 s through fmpy at 1 ms steps, raw fmi2SetReal/DoStep/GetReal with ctypes arrays: "
          f"{best:.3f} s CPU (goal <= 0.5 s)")
    cal = calibration(fmu)
    print(f"0-100 km/h: {cal['t100_s']:.2f} s; peak dry ABS deceleration (100 ms mean): "
          f"{cal['peak_decel_mps2']:.2f} m/s^2; stop from 100 km/h: {cal['stop_m']:.2f} m in {cal['stop_s']:.2f} s")


if __name__ == "__main__":
    main()
