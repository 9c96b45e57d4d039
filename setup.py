"""The build's one step beyond pyproject.toml: the ECU core compiled with mypyc (issue 20).

The in-process loop spends about a fifth of its time in ``ecu.core.step``; compiled, the paper loop
runs at 0.89 of d2cf42d's speed instead of 0.80 (``benchmarks/bench_inprocess.py``, 2026-12-02). The
modules below are the core's functions; ``types``, ``params``, ``strategy`` (a runtime-checked
``Protocol``), the strategies and the region geometry (numpy) stay Python. Set ``CRD_PURE_PYTHON=1`` to skip
the compilation; if it fails (no C compiler), the install goes on with the same modules as Python
and says so. Either way the results are the same (the golden tests run on whichever is installed).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

from setuptools import setup

CORE = [
    "decel_estimate", "degraded", "intent", "modes", "output_gate", "plan", "plausibility", "proximity",
    "relative_stop", "relevance", "speed_estimate", "step", "stopping_path", "track_confirmation", "validity",
    "steering", "planar",
]


def _compiled_core() -> list:
    here = Path(__file__).resolve().parent
    if os.environ.get("CRD_PURE_PYTHON"):
        _remove_compiled(here / "ecu" / "core")
        return []
    try:
        from mypyc.build import mypycify

        # the core's imports (numpy, python-can, the DBC-built enums) are checked only as far as it uses them
        options = ["--ignore-missing-imports", "--follow-imports=silent"]
        return mypycify(options + [str(Path("ecu", "core", f"{name}.py")) for name in CORE], opt_level="3",
                        group_name="ecu.core._compiled")
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - any failure (mypyc exits on one) leaves the core in Python
        print(f"crd: the ECU core stays pure Python ({type(exc).__name__}: {exc})", file=sys.stderr)
        _remove_compiled(here / "ecu" / "core")
        return []


def _remove_compiled(core: Path) -> None:
    """An earlier build's compiled modules would shadow the sources (``import ecu`` refuses them): removed."""
    for name in [*CORE, "_compiled__mypyc"]:
        for built in core.glob(f"{name}.*.so"):
            built.unlink()


setup(ext_modules=_compiled_core())
