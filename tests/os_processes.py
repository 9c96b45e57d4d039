"""Helpers shared by the tests that start child processes: is a PID gone, building a pythonfmu FMU,
and waiting for a child's streamed time series."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path


def process_gone(pid: int) -> bool:
    """True when ``pid`` no longer runs: it does not exist, or it is a zombie waiting for its parent's wait()."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(")")[-1].split()[0] == "Z"
    except FileNotFoundError:
        return True


def build_pythonfmu(script: Path, out_dir: Path, name: str) -> Path:
    """``python -m pythonfmu build`` of ``script`` into ``out_dir``; returns ``out_dir/<name>.fmu``."""
    subprocess.run([sys.executable, "-m", "pythonfmu", "build", "-f", str(script), "-d", str(out_dir)],
                   check=True, capture_output=True)
    return out_dir / f"{name}.fmu"


def last_time_s(csv_path: Path) -> float:
    """The time (s) of the last complete row of a streamed ``timeseries.csv``; -1.0 before there is one."""
    try:
        lines = csv_path.read_text().splitlines()
    except FileNotFoundError:
        return -1.0
    for line in reversed(lines[1:]):
        try:
            return float(line.split(",")[0])
        except ValueError:
            continue  # a line being written
    return -1.0


def wait_for(condition, timeout_s: float, what: str, proc: subprocess.Popen) -> None:
    """Poll ``condition`` every 50 ms while ``proc`` runs; fails naming ``what`` after ``timeout_s``."""
    deadline = time.monotonic() + timeout_s
    while not condition():
        assert proc.poll() is None, f"the child ended early with {proc.returncode}: {proc.stderr.read()}"
        assert time.monotonic() < deadline, f"{what} within {timeout_s} s: nothing streamed"
        time.sleep(0.05)


def crd_signalled_when(args: list[str], ready, what: str, sig: int, check=None) -> tuple[int, str]:
    """Run ``crd ARGS`` as a child; once ``ready()`` (within 60 s) call ``check()`` if given, then send ``sig``.

    Returns the child's exit code and its stderr; the child is killed and reaped on every way out.
    """
    proc = subprocess.Popen([sys.executable, "-m", "cosim.cli.main", *args],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        wait_for(ready, 60.0, what, proc)
        if check is not None:
            check()
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=60.0)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    return proc.returncode, err
