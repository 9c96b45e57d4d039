"""``EcuProcess``: ``crd ecu`` as a child OS process, started and stopped by PID.

The child runs ``python -m ecu --interface I --channel C --config F
[--sim-time]`` (``crd ecu`` as a program of its own, quicker to start and
to exit: :mod:`ecu.__main__`) with the run's :class:`ecu.EcuConfig` written to
``F`` (floats as ``repr``, so they read back bit-identical). Its stdout and
stderr go to files in ``workdir`` (never pipes: a chatty child cannot block).

Stopping is bounded: SIGTERM, and SIGCONT in case it was stopped (the ECU
sets its stop event, shuts its bus down and prints its run summary), then
SIGKILL after ``timeout_s``. :meth:`stop`
is idempotent and is called from ``finally`` blocks, so a child never
outlives its parent's run, on errors and on KeyboardInterrupt too.
"""

from __future__ import annotations

import logging
import os
import select
import signal
import subprocess
import sys
from dataclasses import fields
from pathlib import Path

from ecu import EcuConfig

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
        self.proc = subprocess.Popen(self.argv, stdin=subprocess.DEVNULL, stdout=self._out, stderr=self._err)
        self.returncode: int | None = None
        self._signalled = False
        log.info("started crd ecu, pid %d: %s", self.proc.pid, " ".join(self.argv))

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
                    _wait_exit(self.proc, timeout_s)
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


def _wait_exit(proc: subprocess.Popen, timeout_s: float) -> None:
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
