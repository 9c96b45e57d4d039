"""The plant seam: what the master needs of a vehicle plant, and where it runs.

:class:`Plant` is the typed interface both plant implementations fill in:
:class:`~cosim.world.plant_fmu.FmuPlant` (the FMU in this process, through
fmpy) and :class:`~cosim.world.plant_process.IsolatedPlant` (the same, in a
child process with a watchdog). :func:`open_plant` picks one from
``[plant] isolation``:

* ``"inprocess"``: fastest; a native fault in the FMU kills the run;
* ``"process"``: a crash or hang becomes an error naming the time and the cause;
* ``"auto"`` (default): ``process`` for a third-party FMU, ``inprocess`` for
  our own builtin plant, whose source is tested here.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Protocol

from ..scenarios.config import PlantConfig
from .plant_fmu import FmuPlant, PlantPose, PlantSample
# at import, not in finite_check: a forked run worker (crd paper) would import it again in each process
from .plant_process import _check_finite, _output_names


class Plant(Protocol):
    """A vehicle plant the master steps (SI units: m, m/s, m/s²; commands 0..1)."""

    sha256: str
    fmi_version: int
    fixed_internal_step_s: float | None
    wheel_speeds_mapped: bool  # False: every wheel speed is the vehicle speed (no ABS slip visible)

    def set_actuation(self, throttle: float, brake: float, steering_wheel_angle_rad: float = 0.0,
                      steer_request_rad: float = 0.0) -> None: ...

    def step(self, t_s: float, h_s: float) -> None: ...

    def read(self) -> PlantSample: ...

    def pose(self) -> PlantPose: ...

    def close(self) -> None: ...


def isolation_of(cfg: PlantConfig) -> str:
    """``"inprocess"`` or ``"process"``: ``auto`` resolved by whether the FMU is our builtin one."""
    if cfg.isolation != "auto":
        return cfg.isolation
    return "inprocess" if cfg.fmu == "builtin" else "process"


def open_plant(cfg: PlantConfig, fmu_path: Path) -> Plant:
    """The plant for ``cfg``, instantiated and initialised."""
    if isolation_of(cfg) == "process":
        from .plant_process import IsolatedPlant

        return IsolatedPlant(cfg, fmu_path, cfg.step_timeout_s)
    return FmuPlant(cfg, fmu_path)


def finite_check(cfg: PlantConfig) -> Callable[[PlantSample, float], None]:
    """A check for one sample read at ``t_s``: a NaN or infinite output raises FmiStepError naming both.

    The master calls it once per ECU cycle on what it read (the isolated plant also checks in its
    child). The fast path is one sum: a NaN or an infinity makes ``s - s`` non-zero (so can an
    overflow of the sum, after which the slow path finds every value finite and passes).
    """
    names = _output_names(cfg)

    def check(sample: PlantSample, t_s: float) -> None:
        w = sample.wheel_speeds_mps
        s = (sample.position_m + sample.speed_mps + sample.accel_mps2 + w[0] + w[1] + w[2] + w[3] + sample.y_m
             + sample.yaw_rad + sample.yaw_rate_radps + sample.vx_mps + sample.vy_mps + sample.ax_mps2 + sample.ay_mps2)
        if s - s != 0.0:
            _check_finite(sample, names, t_s)

    return check


def divides_step(internal_step_s: float | None, h_s: float) -> bool:
    """True when ``h_s`` is a whole number (>= 1) of the FMU's fixed internal steps."""
    if not internal_step_s:
        return False
    ratio = h_s / internal_step_s
    return ratio >= 1.0 - 1e-9 and abs(ratio - round(ratio)) <= 1e-9 * ratio
