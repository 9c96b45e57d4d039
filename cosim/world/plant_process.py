"""The plant FMU in a child process, with a watchdog on every call (``[plant] isolation = "process"``).

A native fault in an FMU (``abort()``, a segmentation fault, an endless loop
in ``doStep`` or in ``fmi2Terminate``) must not take the co-simulation with
it. Following the idea of libcosim's proxy-fmu (one OS process per FMU
instance, driven over IPC), :class:`IsolatedPlant` runs an ordinary
:class:`~cosim.world.plant_fmu.FmuPlant` in a child interpreter
(``python -m cosim.world.plant_process FD``) and talks to it over a socket
pair wrapped in :class:`multiprocessing.connection.Connection`. (Not
``multiprocessing.Process``: its ``spawn`` re-runs the caller's ``__main__``.) It offers the same methods as
``FmuPlant``, so the master cannot tell the two apart.

Guarantees:

* every request waits at most ``step_timeout_s`` for its reply; a child that
  does not answer is killed by PID, and a child that died is reaped, and
  either becomes :class:`~cosim.errors.FmiStepError` naming the simulation
  time and the cause (``hung``, ``killed by SIGSEGV``, ``exit 134``...), so
  the master keeps the results so far;
* an output that is not finite (NaN, ±Inf) is an error naming the time and
  the FMU variable;
* :meth:`close` asks the child to terminate the FMU and waits at most
  ``step_timeout_s``; then it kills it. A finished run is never lost to a
  hang in ``terminate``, and no child outlives the run (``close`` is
  idempotent and runs from the master's ``finally``);
* the child ignores SIGINT: Ctrl-C reaches the master, which stops the run
  and kills the child.

Cost: one pipe round trip per ECU cycle (the child steps, then reads every
output and returns them with the step's reply; :meth:`read` and
:meth:`pose` then cost nothing). ``benchmarks/bench_fmu.py``
measures it against the in-process plant.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import signal
import socket
import subprocess
import sys
from multiprocessing.connection import Connection
from pathlib import Path

from ..errors import FmiStepError, PlantError
from ..scenarios.config import PLANAR_OUTPUT_ROLES, PlantConfig
from .fmu_share import file_sha256
from .plant_fmu import FmuPlant, PlantPose, PlantSample

log = logging.getLogger(__name__)

_START_TIMEOUT_S = 30.0  # interpreter start, fmpy import, unzip and instantiate


def _output_names(cfg: PlantConfig) -> list[str]:
    """The mapped output variables, in the order :class:`PlantSample` reports them (for messages)."""
    by_role = {m.role: m.names for m in cfg.outputs}
    wheels = by_role.get("wheel_speeds") or by_role["speed"]
    planar = [(by_role.get(role) or (f"(none: {role})",))[0] for role in PLANAR_OUTPUT_ROLES]
    return [by_role["position"][0], by_role["speed"][0], (by_role.get("accel") or ("(none)",))[0],
            *[wheels[n % len(wheels)] for n in range(4)], *planar]


def _check_finite(sample: PlantSample, names: list[str], t_s: float) -> None:
    values = (sample.position_m, sample.speed_mps, sample.accel_mps2, *sample.wheel_speeds_mps, *sample[4:])
    for name, value in zip(names, values):
        if not math.isfinite(value):
            raise FmiStepError(f"plant FMU output {name!r} is {value} at t = {t_s:.6f} s", time_s=t_s,
                               status="non-finite output")


def _serve(conn: Connection, cfg: PlantConfig, fmu_path: str) -> None:
    """The child: open the FMU, then answer requests until ``close`` or the pipe ends."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        plant = FmuPlant(cfg, Path(fmu_path))
    except PlantError as exc:
        conn.send(("error", type(exc).__name__, str(exc), float("nan"), ""))
        return
    names = _output_names(cfg)
    conn.send(("ready", plant.fixed_internal_step_s, plant.fmi_version, plant.read()))
    while True:
        try:
            request = conn.recv()
        except EOFError:  # the parent is gone
            break
        if request[0] == "close":
            plant.close()
            conn.send(("closed",))
            break
        _, t_s, h_s, throttle, brake, steering, overlay = request
        try:
            plant.set_actuation(throttle, brake, steering, overlay)
            plant.step(t_s, h_s)
            sample = plant.read()
            _check_finite(sample, names, t_s + h_s)
        except FmiStepError as exc:
            conn.send(("error", "FmiStepError", str(exc), exc.time_s, exc.status))
            continue
        conn.send(("ok", sample))


def _cause(exitcode: int | None) -> str:
    if exitcode is None:
        return "no reply"
    if exitcode < 0:
        try:
            return f"killed by {signal.Signals(-exitcode).name}"
        except ValueError:
            return f"killed by signal {-exitcode}"
    return f"exit {exitcode}"


class IsolatedPlant:
    """:class:`FmuPlant`'s interface, served by a child process with a per-call watchdog."""

    def __init__(self, cfg: PlantConfig, fmu_path: Path, step_timeout_s: float) -> None:
        self.path = Path(fmu_path)
        if not self.path.is_file():
            raise PlantError(f"plant FMU not found: expected a file at {self.path}")
        self.sha256 = file_sha256(self.path)
        self.step_timeout_s = step_timeout_s
        self.wheel_speeds_mapped = cfg.output_map("wheel_speeds") is not None  # as FmuPlant reports it
        self._throttle = self._brake = self._steering = self._overlay = 0.0
        ours, theirs = socket.socketpair()
        with theirs:
            self._proc = subprocess.Popen([sys.executable, "-m", __name__, str(theirs.fileno())],
                                          pass_fds=(theirs.fileno(),), stdin=subprocess.DEVNULL)
        self.pid = self._proc.pid
        self._conn: Connection | None = Connection(ours.detach())
        picklable = dataclasses.replace(cfg, parameters=dict(cfg.parameters))  # MappingProxyType does not pickle
        self._conn.send((picklable, str(self.path)))
        reply = self._reply(_START_TIMEOUT_S, t_s=0.0, what="start")
        if reply[0] == "error":
            self.close()
            raise PlantError(reply[2])
        _, self.fixed_internal_step_s, self.fmi_version, self._sample = reply

    def _reply(self, timeout_s: float, t_s: float, what: str) -> tuple:
        """The child's next message, or FmiStepError when it hangs or dies (the child is then gone)."""
        conn, hung = self._conn, True
        try:
            if conn is not None and conn.poll(timeout_s):
                return conn.recv()
        except (EOFError, OSError):  # the child closed its end: it died
            hung = False
            try:
                self._proc.wait(timeout=2.0)
            except subprocess.TimeoutExpired:
                pass
        self._kill()
        cause = f"no reply within {timeout_s:g} s (hung; process killed)" if hung else _cause(self._proc.returncode)
        raise FmiStepError(f"plant FMU process failed in {what} at t = {t_s:.6f} s: {cause}",
                           time_s=t_s, status="hung" if hung else "crashed")

    # -- FmuPlant's interface -------------------------------------------------
    def set_actuation(self, throttle: float, brake: float, steering_wheel_angle_rad: float = 0.0,
                      steer_request_rad: float = 0.0) -> None:
        """Kept until the next :meth:`step`, which sends it with the step."""
        self._throttle, self._brake, self._steering = throttle, brake, steering_wheel_angle_rad
        self._overlay = steer_request_rad

    def step(self, t_s: float, h_s: float) -> None:
        if self._conn is None:
            raise FmiStepError(f"plant FMU process is gone at t = {t_s:.6f} s", time_s=t_s, status="closed")
        try:
            self._conn.send(("step", t_s, h_s, self._throttle, self._brake, self._steering, self._overlay))
        except OSError:
            pass  # a dead child shows in the reply
        reply = self._reply(self.step_timeout_s, t_s, "doStep")
        if reply[0] == "error":
            raise FmiStepError(reply[2], time_s=reply[3], status=reply[4])
        self._sample = reply[1]

    def read(self) -> PlantSample:
        return self._sample

    def pose(self) -> PlantPose:
        s = self._sample
        return PlantPose(s.position_m, s.speed_mps, s.y_m, s.yaw_rad, s.yaw_rate_radps, s.vx_mps, s.vy_mps)

    def close(self) -> None:
        """Terminate the FMU in the child, bounded by ``step_timeout_s``; kill it otherwise. Idempotent."""
        conn = self._conn
        if conn is None:
            return
        if self._proc.poll() is None:
            try:
                conn.send(("close",))
                if conn.poll(self.step_timeout_s):
                    conn.recv()
                else:
                    log.warning("plant FMU process %s: terminate took over %g s; killed", self.pid,
                                self.step_timeout_s)
            except (EOFError, OSError):
                pass
        self._kill()

    def _kill(self) -> None:
        conn, self._conn = self._conn, None
        if self._proc.poll() is None:
            self._proc.kill()  # by PID; SIGKILL cannot be ignored by a looping FMU
        self._proc.wait(timeout=5.0)
        if conn is not None:
            conn.close()

    def __enter__(self) -> "IsolatedPlant":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def _child_main(fd: int) -> None:
    conn = Connection(fd)
    cfg, fmu_path = conn.recv()
    _serve(conn, cfg, fmu_path)


if __name__ == "__main__":
    _child_main(int(sys.argv[1]))
