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
  tear-down of python-can's module graph, about 20 % of the process's CPU
  time (``benchmarks/bench_hil.py`` section 5), which the master would wait for.
"""

from __future__ import annotations

import logging
import os
import sys


def _main() -> None:
    sys.modules.setdefault("asammdf", None)
    from .cli import main  # only now: python-can is imported with it

    code = main(sys.argv[1:])
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    _main()
