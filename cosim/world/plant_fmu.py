"""Any co-simulation FMU (FMI 2 or 3) as the vehicle plant, through fmpy.

Roles (``[plant.inputs]``/``[plant.outputs]``) are resolved to value
references once, at start-up; a mapped name the FMU lacks, or of the wrong
causality, raises :class:`~cosim.errors.MappingError` listing the FMU's
variables of the right causality. In the loop the wrapper calls fmpy's FMI
functions with pre-built ctypes arrays (one set, one step, one get per call),
and turns an FMI error into :class:`~cosim.errors.FmiStepError` naming the
time and the FMI status.

Conversions (SI on our side): output ``si = fmu * scale + offset``; input
``fmu = role * scale + offset``; ``[plant.initial]`` parameters (the initial
speed) like inputs. An ``accel_command`` FMU gets
``throttle * accel_gain_mps2 - brake * brake_gain_mps2`` (m/s²). Wheel
speeds in m/s are the wheel outputs (rad/s) × ``wheel_radius_m``, or the
vehicle speed on every wheel when the FMU has no wheel outputs.
"""

from __future__ import annotations

import ctypes
import logging
import shutil
from pathlib import Path
from typing import NamedTuple

from fmpy import extract
from fmpy.fmi1 import FMICallException

from ..errors import FmiStepError, MappingError, PlantError
from ..scenarios.config import PLANAR_OUTPUT_ROLES, POSE_OUTPUT_ROLES, PlantConfig, SignalMap
from .fmu_share import SHARED, file_sha256, read_md

log = logging.getLogger(__name__)

_STATUS = ("OK", "Warning", "Discard", "Error", "Fatal", "Pending")
_WARNING = 1  # FMI status codes above Warning are errors (as fmpy's own check)
#: the run's warning when ``wheel_speeds_mapped`` is False
DERIVED_WHEEL_SPEEDS = ("plant.outputs.wheel_speeds is not mapped: every wheel speed is the vehicle speed,"
                        " so ABS wheel slip is invisible to the ECU (its speed estimate and the result can"
                        " differ from a plant with wheel outputs)")
_REAL_TYPES = ("Real", "Float64", "Float32")


class PlantSample(NamedTuple):
    """Plant outputs in SI: m, m/s, m/s², four wheel speeds × radius in m/s, and the plane's pose and motion.

    ``y_m``, ``yaw_rad``: the pose point's y and heading; ``yaw_rate_radps``; ``vx_mps``, ``vy_mps``: its
    velocity in the vehicle frame. A plant without those outputs reports 0, 0, 0, its speed, 0.
    ``ax_mps2``, ``ay_mps2``: its acceleration in the vehicle frame (what the ESC's sensor reads); a plant
    without those outputs reports its ``accel`` and ``vx * yaw_rate`` (the steady-state lateral acceleration).
    A tuple: built every cycle, and about four times cheaper to build than a frozen dataclass.
    """

    position_m: float
    speed_mps: float
    accel_mps2: float
    wheel_speeds_mps: tuple[float, float, float, float]
    y_m: float
    yaw_rad: float
    yaw_rate_radps: float
    vx_mps: float
    vy_mps: float
    ax_mps2: float
    ay_mps2: float


class PlantPose(NamedTuple):
    """What a plant step in between ECU cycles reads: the pose and motion of :class:`PlantSample`."""

    position_m: float
    speed_mps: float
    y_m: float
    yaw_rad: float
    yaw_rate_radps: float
    vx_mps: float
    vy_mps: float


#: the output roles in the order the raw outputs are read (the planar ones last)
_OUTPUT_ORDER = ("position", "speed", "accel", "wheel_speeds", *PLANAR_OUTPUT_ROLES)


def _variables_by(md, causality: str) -> list[str]:
    return sorted(v.name for v in md.modelVariables if v.causality == causality)


def _resolve(md, names: tuple[str, ...], causality: str, where: str) -> list:
    by_name = {v.name: v for v in md.modelVariables}
    found = []
    for name in names:
        var = by_name.get(name)
        if var is None or var.causality != causality or (causality != "parameter" and var.type not in _REAL_TYPES):
            actual = "missing" if var is None else f"causality {var.causality!r}, type {var.type}"
            raise MappingError(
                f"{where}: FMU variable {name!r} is {actual}; expected a real {causality}."
                f" The FMU's {causality}s are: {', '.join(_variables_by(md, causality)) or '(none)'}"
            )
        found.append(var)
    return found


class FmuPlant:
    """The plant FMU, instantiated, initialised and ready to :meth:`step`."""

    def __init__(self, cfg: PlantConfig, fmu_path: Path, start_time_s: float = 0.0) -> None:
        self.path = Path(fmu_path)
        if not self.path.is_file():
            raise PlantError(f"plant FMU not found: expected a file at {self.path}")
        shared = SHARED.get(self.path)  # prepared once for many runs (a sweep worker), or None
        self.sha256, md = (shared.sha256, shared.md) if shared else (file_sha256(self.path), read_md(self.path))
        if md.coSimulation is None:
            raise PlantError(f"{self.path}: expected a co-simulation FMU, got model exchange only")
        self.fmi_version = int(md.fmiVersion[0])
        cs = md.coSimulation
        #: FMI 3 ``fixedInternalStepSize`` (s) when the FMU declares one and takes variable steps, else None
        self.fixed_internal_step_s: float | None = (
            float(cs.fixedInternalStepSize)
            if getattr(cs, "fixedInternalStepSize", None) and cs.canHandleVariableCommunicationStepSize else None)
        self._cfg = cfg
        self._md = md
        self._resolve_roles()
        self._shared = shared if shared is not None and shared.claim() else None  # busy: load a copy
        self._unzipdir = self._shared.unzipdir if self._shared is not None else extract(str(self.path))
        self._fmu = None
        try:
            self._open(start_time_s)
        except BaseException:
            self.close()
            raise

    # -- set-up -----------------------------------------------------------
    def _resolve_roles(self) -> None:
        md, cfg = self._md, self._cfg
        self._in_maps: list[SignalMap] = list(cfg.inputs)
        in_vars = [_resolve(md, m.names, "input", f"plant.inputs.{m.role}")[0] for m in self._in_maps]
        out = {m.role: (m, _resolve(md, m.names, "output", f"plant.outputs.{m.role}")) for m in cfg.outputs}
        self._params = [(v, cfg.parameters[v.name]) for v in
                        _resolve(md, tuple(cfg.parameters), "parameter", "plant.parameters")]
        initial = {m.role: m for m in cfg.initial}
        for _, role, value in cfg.initial_values():  # [plant.initial]: fmu = value * scale + offset
            m = initial[role]
            var = _resolve(md, m.names, "parameter", f"plant.initial.{m.role}")[0]
            self._params.append((var, value * m.scale + m.offset))
        self._in_vr = (ctypes.c_uint32 * len(in_vars))(*[v.valueReference for v in in_vars])
        self._in_val = (ctypes.c_double * len(in_vars))()
        # set_actuation's table: (index, role, scale, offset) of the inputs the commands drive
        self._actuated = tuple((i, m.role, m.scale, m.offset) for i, m in enumerate(self._in_maps)
                               if m.role != "road_friction")
        self._accel_gain, self._brake_gain = cfg.accel_gain_mps2, cfg.brake_gain_mps2
        for i, m in enumerate(self._in_maps):
            if m.role == "road_friction":
                self._in_val[i] = cfg.road_friction * m.scale + m.offset
        self._out_maps = [out[r][0] for r in _OUTPUT_ORDER if r in out]
        out_vrs = [v.valueReference for r in _OUTPUT_ORDER if r in out for v in out[r][1]]
        self._out_vr = (ctypes.c_uint32 * len(out_vrs))(*out_vrs)
        self._out_val = (ctypes.c_double * len(out_vrs))()
        self._conversions(cfg.wheel_radius_m)

    def _conversions(self, radius_m: float) -> None:
        """read()'s and pose()'s (index into the raw outputs, scale, offset) per SI value, fixed at start-up."""
        conv, i = {}, 0
        for m in self._out_maps:
            conv[m.role] = [(i + j, m.scale, m.offset) for j in range(len(m.names))]
            i += len(m.names)
        self.wheel_speeds_mapped = "wheel_speeds" in conv  # False: derived from the speed (no ABS slip)
        wheels = [(j, s * radius_m, o * radius_m) for j, s, o in conv["wheel_speeds"]] if "wheel_speeds" in conv \
            else conv["speed"]  # fewer than 4 names: repeated in order; none: the speed on every wheel
        self._read_conv = (conv["position"][0], conv["speed"][0], conv["accel"][0] if "accel" in conv else None,
                           tuple(wheels[n % len(wheels)] for n in range(4)))
        planar = [conv[r][0] if r in conv else None for r in PLANAR_OUTPUT_ROLES]
        self.planar_mapped = any(c is not None for c in planar)  # False: y, yaw, yaw rate, vy 0 and vx the speed
        pose, self._accel_conv = planar[:len(POSE_OUTPUT_ROLES)], tuple(planar[len(POSE_OUTPUT_ROLES):])
        # pose(): the position, speed and pose outputs only, read into an array of their own
        picked = [conv["position"][0], conv["speed"][0], *(c for c in pose if c is not None)]
        self._pv_vr = (ctypes.c_uint32 * len(picked))(*[self._out_vr[j] for j, _, _ in picked])
        self._pv_val = (ctypes.c_double * len(picked))()
        at = iter(range(2, len(picked)))
        # (index in read()'s array, index in pose()'s array, scale, offset) per planar role, None where unmapped
        self._planar_conv = tuple(None if c is None else (c[0], next(at), c[1], c[2]) for c in pose)

    def _open(self, start_time_s: float) -> None:
        from fmpy.fmi2 import FMU2Slave
        from fmpy.fmi3 import FMU3Slave

        cls = FMU2Slave if self.fmi_version == 2 else FMU3Slave
        guid = self._md.guid if self.fmi_version == 2 else self._md.instantiationToken
        try:
            self._fmu = self._shared.slave if self._shared is not None else None
            if self._fmu is None:
                self._fmu = cls(guid=guid, unzipDirectory=self._unzipdir,
                                modelIdentifier=self._md.coSimulation.modelIdentifier, instanceName="plant")
                if self._shared is not None:
                    self._shared.slave = self._fmu
            self._fmu.instantiate()
            if self.fmi_version == 2:
                self._fmu.setupExperiment(startTime=start_time_s)
            self._set_parameters()
            if self.fmi_version == 2:
                self._fmu.enterInitializationMode()
            else:
                self._fmu.enterInitializationMode(startTime=start_time_s)
            self._bind_hot_path()
            self.set_actuation(0.0, 0.0)
            self._fmu.exitInitializationMode()
        except FMICallException as exc:
            raise PlantError(f"{self.path}: FMU refused initialisation: {exc}"
                             " (check [plant.parameters] against the FMU's ranges)") from exc
        except OSError as exc:
            raise PlantError(f"{self.path}: cannot load the FMU's binary: {exc}") from exc

    def _set_parameters(self) -> None:
        fmu, v2 = self._fmu, self.fmi_version == 2
        for var, value in self._params:
            vr = [var.valueReference]
            if var.type == "Boolean":
                fmu.setBoolean(vr, [bool(value)])
            elif var.type in ("Integer", "Int32", "Int64"):
                (fmu.setInteger if v2 else fmu.setInt32)(vr, [int(value)])
            else:
                (fmu.setReal if v2 else fmu.setFloat64)(vr, [float(value)])

    def _bind_hot_path(self) -> None:
        """Bind fmpy's raw ctypes functions and their argument tuples once.

        fmpy's ``FMU2Slave.fmi2DoStep`` etc. go through ``_FMU._call`` (a dict
        look-up, an optional call logger, a status check) and a Python method per
        call; the loop makes three to twelve such calls per 10 ms cycle. The raw
        functions (``fmu._functions``, argtypes set by fmpy) with preallocated
        ctypes arrays and prebuilt argument tuples save about 1 µs per call; the
        status check fmpy would make (> Warning is an error) is made here.
        """
        fmu = self._fmu
        raw, c = fmu._functions, fmu.component
        if self.fmi_version == 2:
            self._raw_step = raw["fmi2DoStep"]
            self._step_tail = (1,)  # noSetFMUStatePriorToCurrentPoint
            get, set_ = raw["fmi2GetReal"], raw["fmi2SetReal"]
            arrays = lambda vr, val: (c, vr, len(vr), val)  # noqa: E731 - fmi2: (c, vrs, n, values)
        else:
            self._raw_step = raw["fmi3DoStep"]
            flags = [ctypes.c_bool() for _ in range(3)]
            self._last_t = ctypes.c_double()
            self._step_tail = (True, *[ctypes.byref(f) for f in flags], ctypes.byref(self._last_t))
            get, set_ = raw["fmi3GetFloat64"], raw["fmi3SetFloat64"]
            arrays = lambda vr, val: (c, vr, len(vr), val, len(val))  # noqa: E731 - fmi3 adds nValues
        self._component = c
        self._get, self._set = get, set_
        self._get_out = arrays(self._out_vr, self._out_val)
        self._get_pv = arrays(self._pv_vr, self._pv_val)
        self._set_in = arrays(self._in_vr, self._in_val) if len(self._in_val) else None
        self._fname = {"step": f"fmi{self.fmi_version}DoStep", "get outputs": get.__name__,
                       "set inputs": set_.__name__}

    # -- the loop -----------------------------------------------------------
    def set_actuation(self, throttle: float, brake: float, steering_wheel_angle_rad: float = 0.0,
                      steer_request_rad: float = 0.0) -> None:
        """Set the plant's inputs from throttle and brake commands (0..1), the driver's steering-wheel angle (rad)
        and the ECU's road-wheel angle overlay (rad, the ``steer_request`` role: optional, ignored unmapped)."""
        val = self._in_val
        for i, role, scale, offset in self._actuated:  # road friction is constant: written once, at start-up
            if role == "throttle":
                x = throttle
            elif role == "brake":
                x = brake
            elif role == "steering_wheel_angle":
                x = steering_wheel_angle_rad
            elif role == "steer_request":
                x = steer_request_rad
            else:  # accel_command
                x = throttle * self._accel_gain - brake * self._brake_gain
            val[i] = x * scale + offset
        if self._set_in is not None and self._fmu is not None:
            if (status := self._set(*self._set_in)) > _WARNING:
                self._fail(status, None, "set inputs")

    def _fail(self, status: int, t_s: float | None, what: str) -> None:
        name = f"fmi{self.fmi_version}{_STATUS[status] if 0 <= status < 6 else status}"
        at = "" if t_s is None else f" at t = {t_s:.6f} s"
        raise FmiStepError(f"plant FMU failed to {what}{at}: {self._fname[what]} returned {name}",
                           time_s=t_s if t_s is not None else float("nan"), status=name)

    def step(self, t_s: float, h_s: float) -> None:
        """Advance from communication point ``t_s`` by ``h_s`` seconds."""
        if (status := self._raw_step(self._component, t_s, h_s, *self._step_tail)) > _WARNING:
            self._fail(status, t_s, "step")

    def _planar(self, raw: list, speed_mps: float, at: int) -> tuple[float, float, float, float, float]:
        """(y, yaw, yaw rate, vx, vy) from raw values (``at``: 0 in read()'s array, 1 in pose()'s)."""
        y, yaw, rate, vx, vy = (None if c is None else raw[c[at]] * c[2] + c[3] for c in self._planar_conv)
        return (0.0 if y is None else y, 0.0 if yaw is None else yaw, 0.0 if rate is None else rate,
                speed_mps if vx is None else vx, 0.0 if vy is None else vy)

    def pose(self) -> PlantPose:
        """Position, speed and the planar outputs only: the cheap read used between ECU cycles."""
        if (status := self._get(*self._get_pv)) > _WARNING:
            self._fail(status, None, "get outputs")
        (_, sp, op), (_, sv, ov) = self._read_conv[0], self._read_conv[1]
        raw = self._pv_val[:]
        v = raw[1] * sv + ov
        if not self.planar_mapped:
            return PlantPose(raw[0] * sp + op, v, 0.0, 0.0, 0.0, v, 0.0)
        return PlantPose(raw[0] * sp + op, v, *self._planar(raw, v, 1))

    def read(self) -> PlantSample:
        """All mapped outputs, in SI."""
        if (status := self._get(*self._get_out)) > _WARNING:
            self._fail(status, None, "get outputs")
        # one slice copies the ctypes array into a list, which is cheaper to index than ctypes
        raw = self._out_val[:]
        (ip, sp, op), (iv, sv, ov), accel, ((j0, s0, o0), (j1, s1, o1), (j2, s2, o2), (j3, s3, o3)) = self._read_conv
        a = 0.0 if accel is None else raw[accel[0]] * accel[1] + accel[2]
        v = raw[iv] * sv + ov
        wheels = (raw[j0] * s0 + o0, raw[j1] * s1 + o1, raw[j2] * s2 + o2, raw[j3] * s3 + o3)
        if not self.planar_mapped:  # ay: vx * yaw rate, as below
            return PlantSample(raw[ip] * sp + op, v, a, wheels, 0.0, 0.0, 0.0, v, 0.0, a, v * 0.0)
        y, yaw, rate, vx, vy = self._planar(raw, v, 0)
        cx, cy = self._accel_conv
        return PlantSample(raw[ip] * sp + op, v, a, wheels, y, yaw, rate, vx, vy,
                           a if cx is None else raw[cx[0]] * cx[1] + cx[2],
                           vx * rate if cy is None else raw[cy[0]] * cy[1] + cy[2])

    def close(self) -> None:
        """Terminate and free the FMU; safe to call twice."""
        fmu, self._fmu = self._fmu, None
        if fmu is not None and self._shared is not None:
            self._shared.release(fmu)
        elif fmu is not None:
            try:
                fmu.terminate()
            except FMICallException as exc:
                log.warning("plant FMU terminate failed: %s", exc)
            try:
                fmu.freeInstance()
            except Exception as exc:  # noqa: BLE001 - best effort after a failure
                log.warning("plant FMU freeInstance failed: %s", exc)
        shared, self._shared = self._shared, None
        if shared is not None:
            self._unzipdir = None  # the shared extraction outlives this plant
            shared.unclaim()
        if self._unzipdir:
            shutil.rmtree(self._unzipdir, ignore_errors=True)
            self._unzipdir = None

    def __enter__(self) -> "FmuPlant":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
