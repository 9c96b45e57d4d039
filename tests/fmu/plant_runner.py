"""Drive the plant FMU through fmpy for the tests: FMU2Slave/FMU3Slave directly.

``run_plant`` steps at ``start + k * comm_step_s`` (integer counter), applies the
inputs a schedule returns for each communication point, and records the outputs
after every step. It also captures the FMU's log messages.
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Sequence

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE
from fmpy.fmi2 import fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE
from fmpy.fmi3 import FMU3Slave
from fmpy.logging import addLoggerProxy

OUTPUTS = ("x", "v", "a", "wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr",
           "brake_pressure", "drive_force")
Schedule = Callable[[float], dict[str, float]]

_libc = ctypes.CDLL(None)
_libc.calloc.restype = ctypes.c_void_p
_libc.calloc.argtypes = [ctypes.c_size_t, ctypes.c_size_t]
_libc.free.argtypes = [ctypes.c_void_p]


@dataclass
class PlantHandle:
    """An instantiated FMU plus the messages it logged as (status, text)."""

    slave: object
    fmi_version: int
    vrs: dict[str, int]
    messages: list[tuple[int, str]] = field(default_factory=list)
    _keep: list = field(default_factory=list)

    def set(self, **values: float) -> None:
        reals = {k: v for k, v in values.items() if not isinstance(v, bool)}
        bools = {k: v for k, v in values.items() if isinstance(v, bool)}
        if reals:
            refs = [self.vrs[k] for k in reals]
            if self.fmi_version == 2:
                self.slave.setReal(refs, list(reals.values()))
            else:
                self.slave.setFloat64(refs, list(reals.values()))
        if bools:
            self.slave.setBoolean([self.vrs[k] for k in bools], list(bools.values()))

    def get(self, *names: str) -> list[float]:
        refs = [self.vrs[n] for n in names]
        return self.slave.getReal(refs) if self.fmi_version == 2 else self.slave.getFloat64(refs)

    def log_text(self) -> str:
        return "\n".join(text for _, text in self.messages)


_EXTRACTED: dict[Path, tuple[str, object]] = {}


def _unpacked(fmu: Path) -> tuple[str, object]:
    if fmu not in _EXTRACTED:
        _EXTRACTED[fmu] = (extract(str(fmu)), read_model_description(str(fmu)))
    return _EXTRACTED[fmu]


def open_plant(fmu: Path, fmi_version: int) -> PlantHandle:
    """Instantiate (logging on) but do not initialise."""
    unzipdir, md = _unpacked(Path(fmu))
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    cls = FMU2Slave if fmi_version == 2 else FMU3Slave
    slave = cls(guid=md.guid if fmi_version == 2 else md.instantiationToken, unzipDirectory=unzipdir,
                modelIdentifier=md.coSimulation.modelIdentifier, instanceName="plant")
    handle = PlantHandle(slave=slave, fmi_version=fmi_version, vrs=vrs)
    if fmi_version == 2:
        def log2(env, name, status, category, message):
            handle.messages.append((status, message.decode()))
        cbs = fmi2CallbackFunctions()
        cbs.logger = fmi2CallbackLoggerTYPE(log2)
        cbs.allocateMemory = fmi2CallbackAllocateMemoryTYPE(_libc.calloc)
        cbs.freeMemory = fmi2CallbackFreeMemoryTYPE(_libc.free)
        addLoggerProxy(ctypes.byref(cbs))
        handle._keep.append(cbs)
        slave.instantiate(callbacks=cbs, loggingOn=True)
    else:
        def log3(env, status, category, message):
            handle.messages.append((status, message.decode()))
        slave.instantiate(loggingOn=True, logMessage=log3)
    return handle


def initialise(handle: PlantHandle, params: dict[str, float] | None = None) -> None:
    if handle.fmi_version == 2:
        handle.slave.setupExperiment(startTime=0.0)
    if params:
        handle.set(**params)
    handle.slave.enterInitializationMode()
    handle.slave.exitInitializationMode()


def _record(fmu: Path, fmi_version: int, steps: Iterable[tuple[float, float]], schedule: Schedule | None,
            params: dict[str, float] | None, outputs: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Initialise, then for each (t, h): set the schedule's inputs at t, doStep(t, h), read ``outputs``."""
    handle = open_plant(fmu, fmi_version)
    try:
        initialise(handle, params)
        rows = [[0.0, *handle.get(*outputs)]]
        for t, h in steps:
            if schedule is not None:
                handle.set(**schedule(t))
            handle.slave.doStep(t, h)
            rows.append([t + h, *handle.get(*outputs)])
        handle.slave.terminate()
    finally:
        handle.slave.freeInstance()
    data = np.array(rows)
    return {"t": data[:, 0], **{name: data[:, i + 1] for i, name in enumerate(outputs)}}


def run_plant_at(fmu: Path, fmi_version: int, points_us: Sequence[int], schedule: Schedule | None = None,
                 params: dict[str, float] | None = None, outputs: tuple[str, ...] = OUTPUTS,
                 ) -> dict[str, np.ndarray]:
    """Step through the communication points ``points_us[k] * 1e-6`` s (integers from 0, any
    spacing); returns arrays keyed "t" and each of ``outputs``."""
    steps = ((a * 1e-6, b * 1e-6 - a * 1e-6) for a, b in zip(points_us[:-1], points_us[1:]))
    return _record(fmu, fmi_version, steps, schedule, params, outputs)


def run_plant(fmu: Path, fmi_version: int, stop_s: float, comm_step_s: float,
              schedule: Schedule | None = None, params: dict[str, float] | None = None,
              outputs: tuple[str, ...] = OUTPUTS) -> dict[str, np.ndarray]:
    """Simulate to ``stop_s``; returns arrays keyed "t" and each output (row 0 is t = 0)."""
    n = int(round(stop_s / comm_step_s))
    steps = ((k * comm_step_s, comm_step_s) for k in range(n))
    run = _record(fmu, fmi_version, steps, schedule, params, outputs)
    run["t"] = np.arange(n + 1) * comm_step_s
    return run
