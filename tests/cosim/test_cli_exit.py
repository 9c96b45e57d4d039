"""The ``crd`` command's exit: its exit code, its output (an error as one line) and the exit handlers run."""

from __future__ import annotations

import subprocess
import sys

PROGRAM = """
import atexit, sys
atexit.register(lambda: print("exit handler ran", file=sys.stderr))
from cosim.cli.main import main
sys.argv = ["crd"] + sys.argv[1:]
sys.exit(main())
"""


def _crd(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", PROGRAM, *args], capture_output=True, text=True, timeout=120)


def test_the_command_keeps_its_exit_code_output_and_exit_handlers():
    ok = _crd("scenarios")
    assert ok.returncode == 0 and "paper_cyclist" in ok.stdout and ok.stderr.endswith("exit handler ran\n")
    bad = _crd("run", "no_such_scenario")
    assert bad.returncode == 1 and bad.stderr.startswith("error: no_such_scenario")
    assert bad.stderr.endswith("exit handler ran\n")
