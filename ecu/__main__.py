"""``python -m ecu ARGS``: ``crd ecu ARGS`` as a program of its own; how the co-simulation spawns the ECU.

Same arguments, output and exit codes as ``crd ecu`` (:func:`ecu.cli.main`).
Only its start and its end differ, which a spawned ECU pays on every run of
``--ecu process`` (the master waits for the ECU to join, and for its exit):

* it imports neither ``cosim`` nor the ``crd`` dispatcher and its other
  subcommands;
* asammdf is marked absent before python-can is imported: ``import can``
  imports asammdf (and pandas with it, about 1 s) whenever it is installed
  (the ``crd[mdf]`` extra), and the ECU writes no MF4 file (``crd`` does the
  same, see ``cosim.cli.main``);
* it ends with ``os._exit`` once its output is flushed. The run is over by
  then (bus shut down, summary printed); what is left is the interpreter's
  tear-down of python-can's module graph, about a sixth of the process's
  CPU time (measured), which the master would wait for.

``python -m ecu --args-from-stdin`` is a spare started ahead of a run
(``cosim.link.ecu_process.prepare_spare``): after its imports it waits for one
JSON line ``{"argv": [...], "stdout": path, "stderr": path}``, points its
standard output and error at those files and runs as ``python -m ecu ARGV``;
at the end of its stdin (nobody claimed it) it exits 0 without a word.
"""

from __future__ import annotations

import json
import logging
import os
import sys

#: the one argument of a spare (cosim.link.ecu_process starts spares with it)
SPARE_FLAG = "--args-from-stdin"


def _main() -> None:
    sys.modules.setdefault("asammdf", None)
    from .cli import main  # only now: python-can is imported with it

    argv = sys.argv[1:]
    if argv == [SPARE_FLAG]:
        argv = _claimed_arguments()
        if argv is None:
            os._exit(0)
    code = main(argv)
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


def _claimed_arguments() -> list[str] | None:
    """A spare's arguments, once the master sends them (None: it never will); output goes to its files."""
    line = sys.stdin.buffer.readline()
    if not line:
        return None
    request = json.loads(line)
    for fd, key in ((1, "stdout"), (2, "stderr")):
        target = os.open(request[key], os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o600)
        os.dup2(target, fd)
        os.close(target)
    return [str(arg) for arg in request["argv"]]


if __name__ == "__main__":
    _main()
