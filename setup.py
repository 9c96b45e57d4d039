"""The build's one step beyond pyproject.toml: the ECU core compiled with mypyc (issue 20).

The in-process loop spends about a fifth of its time in ``ecu.core.step``; compiled, the paper loop
runs at 0.89 of d2cf42d's speed instead of 0.80 (``benchmarks/bench_inprocess.py``, 2026-12-02). The
modules below are the core's functions; ``types``, ``params``, ``strategy`` (a runtime-checked
``Protocol``) and the strategies stay Python. The stopping region's evaluation (:data:`REGION`: numpy on
whole arrays, its cost numpy's per-call overhead and the Python between the calls) and the rules that read
it every cycle (crossing vehicles, lane change, narrowing, reciprocal split, tightened bounds) are compiled in a
group of its own, which saves about a fifth of ``decide`` (``benchmarks/bench_region.py``, 2026-12-02) and
whose failure leaves the core's compiled. Set ``CRD_PURE_PYTHON=1`` to skip
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
    "steering", "lane_change_tracking", "planar",
]
#: the stopping region's modules on the step's path (``ecu/core/region``), compiled in their own group
REGION = ["region/objects", "region/paths", "region/overlap", "region/road", "region/decision", "region/crossing",
          "region/lane_change", "region/narrowing", "region/reciprocal", "region/tightening", "region/evasion"]
#: mypyc's options: the core's imports (numpy, python-can, the DBC-built enums) are checked only as far as it uses
#: them
OPTIONS = ["--ignore-missing-imports", "--follow-imports=silent"]


def _compiled_core() -> list:
    here = Path(__file__).resolve().parent
    if os.environ.get("CRD_PURE_PYTHON"):
        _remove_compiled(here / "ecu" / "core", [*CORE, "_compiled__mypyc", *REGION, "region/_compiled__mypyc"])
        return []
    return _compiled(here, CORE, "ecu.core._compiled") + _compiled(here, REGION, "ecu.core.region._compiled")


def _compiled(here: Path, modules: list[str], group: str) -> list:
    """The ``modules`` of ``ecu/core`` compiled as one mypyc group; none (their sources run) if that fails."""
    try:
        from mypyc.build import mypycify

        return mypycify(OPTIONS + [str(Path("ecu", "core", f"{name}.py")) for name in modules], opt_level="3",
                        group_name=group)
    except (Exception, SystemExit) as exc:  # noqa: BLE001 - any failure (mypyc exits on one) leaves them in Python
        print(f"crd: {group} stays pure Python ({type(exc).__name__}: {exc})", file=sys.stderr)
        _remove_compiled(here / "ecu" / "core", [*modules, group.removeprefix("ecu.core.").replace(".", "/") + "__mypyc"])
        return []


def _remove_compiled(core: Path, modules: list[str]) -> None:
    """An earlier build's compiled modules (and their group's runtime) would shadow the sources (``import ecu``
    refuses them): removed."""
    for name in modules:
        for built in core.glob(f"{name}.*.so"):
            built.unlink()


setup(ext_modules=_compiled_core())
