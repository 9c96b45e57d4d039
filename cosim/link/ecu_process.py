"""``EcuProcess``: ``crd ecu`` as a child OS process, started and stopped by PID.

The child runs ``python -m ecu --interface I --channel C --config F
[--sim-time]`` (``crd ecu`` as a program of its own, quicker to start and
to exit: :mod:`ecu.__main__`) with the run's :class:`ecu.EcuConfig` written to
``F`` (floats as ``repr``, so they read back bit-identical). Its stdout and
stderr go to files in ``workdir`` (never pipes: a chatty child cannot block).

A spare (:func:`prepare_spare`): once a lock-step run's ECU has joined, a
second ``python -m ecu --args-from-stdin`` is started, which does its imports
(most of an ECU's ~0.15 s start-up) and then waits for one line on its stdin.
The next :class:`EcuProcess` of this process claims it, if it is still
waiting and the working directory and environment are unchanged, by sending
the arguments and its output files; otherwise it starts a fresh child as
before. So in a series of runs (``crd paper --ecu process``: three strategies)
only the first waits for a whole start-up, and each ECU is still one process
of its own run, with that run's config and fresh key file, stopped by PID.
A spare that is never claimed is killed by PID at exit (:func:`discard_spare`,
``atexit``), and exits by itself at the end of its stdin if this process dies.

Stopping is bounded: SIGTERM, and SIGCONT in case it was stopped (the ECU
sets its stop event, shuts its bus down and prints its run summary), then
SIGKILL after ``timeout_s``. :meth:`stop`
is idempotent and is called from ``finally`` blocks, so a child never
outlives its parent's run, on errors and on KeyboardInterrupt too.
"""

from __future__ import annotations

import atexit
import json
import logging
import os
import select
import signal
import subprocess
import sys
import threading
from dataclasses import dataclass, fields
from pathlib import Path

from ecu import EcuConfig
from ecu.__main__ import SPARE_FLAG  # the argument that makes python -m ecu a spare

from ..scenarios.toml_writer import dumps

log = logging.getLogger(__name__)

#: EcuConfig fields the command line sets, not the TOML file.
_CLI_FIELDS = ("sim_time",)


def write_ecu_config(path: Path, config: EcuConfig) -> Path:
    """``config`` as an ``[ecu]`` TOML table that ``EcuConfig.from_toml`` reads back exactly."""
    table = {f.name: getattr(config, f.name) for f in fields(config) if f.init and f.name not in _CLI_FIELDS}
    path.write_text(dumps({"ecu": table}, header="ECU settings written by the co-simulation for crd ecu"))
    return path


class EcuProcess:
    """One ``crd ecu`` child process on ``interface``/``channel``."""

    def __init__(self, interface: str, channel: str, config: EcuConfig, sim_time: bool, workdir: Path) -> None:
        self.workdir = Path(workdir)
        config_path = write_ecu_config(self.workdir / "ecu.toml", config)
        self.argv = [sys.executable, "-m", "ecu", "--interface", interface,
                     "--channel", channel, "--config", str(config_path)]
        if sim_time:
            self.argv.append("--sim-time")
        self._out = open(self.workdir / "ecu.stdout", "wb")
        self._err = open(self.workdir / "ecu.stderr", "wb")
        spare = _claim_spare(self.argv[3:], self.workdir)
        self.proc = spare or subprocess.Popen(self.argv, stdin=subprocess.DEVNULL, stdout=self._out, stderr=self._err)
        self.returncode: int | None = None
        self._signalled = False
        log.info("%s crd ecu, pid %d: %s", "claimed the spare" if spare else "started", self.proc.pid,
                 " ".join(self.argv))

    @property
    def pid(self) -> int:
        return self.proc.pid

    def alive(self) -> bool:
        return self.proc.poll() is None

    def signal_stop(self) -> None:
        """Ask the child to stop (SIGTERM, and SIGCONT in case it was stopped), once; :meth:`stop` waits."""
        if not self._signalled and self.returncode is None and self.proc.poll() is None:
            self._signalled = True  # twice could hit the default handler the child restores as it ends
            self.proc.send_signal(signal.SIGTERM)
            self.proc.send_signal(signal.SIGCONT)  # a stopped child (SIGSTOP) handles SIGTERM only when continued

    def stop(self, timeout_s: float = 5.0) -> int:
        """SIGTERM, wait up to ``timeout_s``, then SIGKILL; returns the exit code. Idempotent."""
        if self.returncode is None:
            if self.proc.poll() is None:
                self.signal_stop()
                try:
                    wait_exit(self.proc, timeout_s)
                except subprocess.TimeoutExpired:
                    log.warning("crd ecu pid %d ignored SIGTERM for %.1f s; killing it", self.pid, timeout_s)
                    self.proc.kill()
                    self.proc.wait(timeout=timeout_s)
            self.returncode = self.proc.returncode
            self._out.close()
            self._err.close()
        return self.returncode

    def output(self) -> str:
        """What the child printed (stdout, then stderr); complete once it has stopped."""
        text = []
        for name in ("ecu.stdout", "ecu.stderr"):
            path = self.workdir / name
            if path.exists():
                text.append(path.read_text(errors="replace").strip())
        return "\n".join(t for t in text if t)


@dataclass
class _Spare:
    """A waiting ``python -m ecu --args-from-stdin`` and what it was started with."""

    proc: subprocess.Popen
    owner_pid: int
    cwd: str
    environ: dict[str, str]

    def fits(self) -> bool:
        """Claimable here: ours (not a forked parent's), same directory and environment, still waiting."""
        try:
            same_place = self.cwd == os.getcwd() and self.environ == dict(os.environ)
        except OSError:  # the working directory is gone
            same_place = False
        return self.owner_pid == os.getpid() and same_place and self.proc.poll() is None

    def stop(self) -> None:
        """Kill it by PID and reap it (it holds no bus and no file of a run)."""
        if self.owner_pid == os.getpid():
            if self.proc.poll() is None:
                self.proc.kill()
            self.proc.wait()
            self.proc.stdin.close()


_spare: _Spare | None = None
_spare_lock = threading.Lock()


def prepare_spare() -> None:
    """Start a spare ECU process for the next run, unless one is waiting (see the module docstring)."""
    global _spare
    with _spare_lock:
        if _spare is not None and _spare.fits():
            return
        old, _spare = _spare, None
        if old is not None:
            old.stop()
        proc = subprocess.Popen([sys.executable, "-m", "ecu", SPARE_FLAG], stdin=subprocess.PIPE, bufsize=0,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _spare = _Spare(proc, os.getpid(), os.getcwd(), dict(os.environ))
        log.info("started a spare crd ecu for the next run, pid %d", proc.pid)


def spare_pid() -> int | None:
    """PID of the waiting spare, if there is one (for tests and benchmarks)."""
    spare = _spare
    return spare.proc.pid if spare is not None else None


def discard_spare() -> None:
    """Kill the waiting spare, if any, by its PID: at exit, or where a series of runs is to start cold."""
    global _spare
    with _spare_lock:
        spare, _spare = _spare, None
    if spare is not None:
        spare.stop()


atexit.register(discard_spare)


def _claim_spare(args: list[str], workdir: Path) -> subprocess.Popen | None:
    """The waiting spare, given ``args`` and the run's output files; None if there is none that fits."""
    global _spare
    with _spare_lock:
        spare, _spare = _spare, None
    if spare is None:
        return None
    if not spare.fits():
        spare.stop()
        return None
    request = {"argv": args, "stdout": str(workdir / "ecu.stdout"), "stderr": str(workdir / "ecu.stderr")}
    try:
        spare.proc.stdin.write(json.dumps(request).encode() + b"\n")  # a few hundred bytes: fits the pipe
        spare.proc.stdin.close()
    except OSError:  # it died since fits(): start a fresh one instead
        spare.stop()
        return None
    return spare.proc


def wait_exit(proc: subprocess.Popen, timeout_s: float) -> None:
    """``proc.wait(timeout_s)``, but woken the moment the child exits.

    ``Popen.wait`` with a timeout polls with sleeps that double up to 50 ms, so a
    child that exits after 20 ms is often seen 10 to 30 ms late; a pidfd (Linux
    5.3) becomes readable at the exit itself. Raises ``subprocess.TimeoutExpired``.
    """
    try:
        fd = os.pidfd_open(proc.pid)
    except (AttributeError, OSError):  # no pidfd here (or the child is already reaped)
        proc.wait(timeout=timeout_s)
        return
    try:
        if not select.select([fd], [], [], timeout_s)[0]:
            raise subprocess.TimeoutExpired(proc.args, timeout_s)
    finally:
        os.close(fd)
    proc.wait(timeout=timeout_s)
