"""Helpers shared by the tests that start child processes: is a PID gone, and building a pythonfmu FMU."""

from __future__ import annotations

import os
import subprocess
import sys
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
