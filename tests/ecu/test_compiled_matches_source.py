"""The compiled ECU core decides as its Python source does, in the plane too.

The golden drives (``test_step_golden.py``) carry no planar tracks, so they do not reach the stopping
region, the crossing tightening or the way-out rules, all of which mypyc compiles (``setup.py``). Here
the bundled fleet scene ``crossing`` (two equipped cars that see each other as radar tracks: the
region, the crossing proximity, the tightening dance) is run twice in fresh interpreters: once with the
installed core, once with a copy of ``ecu/`` that holds only the sources. Every record's rows must be
the same, to the last bit. Skipped when the core is not compiled (``CRD_PURE_PYTHON=1``).
"""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import ecu

ECU_DIR = Path(ecu.__file__).resolve().parent
SCRIPT = """
import hashlib, sys
import ecu.core.planar
from cosim.cli.fleet import find_scene
from cosim.fleet.config import load_fleet
from cosim.fleet.output import run_fleet
for way_out in ("none", "right_of_way"):
    record, _ = run_fleet(load_fleet(find_scene("crossing"), way_out), None)
    for r in record.records:
        print(way_out, hashlib.sha256(repr(r.rows).encode()).hexdigest(), len(r.rows))
print(type(ecu.core.planar).__name__, getattr(ecu.core.planar, "__file__", ""), file=sys.stderr)
"""


def _run(tmp_path: Path, pythonpath: str | None) -> tuple[str, str]:
    env = dict(os.environ)
    if pythonpath is not None:
        env["PYTHONPATH"] = pythonpath
    done = subprocess.run([sys.executable, "-c", SCRIPT], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout, done.stderr


@pytest.mark.slow
def test_the_compiled_core_gives_the_sources_results_in_a_fleet(tmp_path):
    if not glob.glob(str(ECU_DIR / "core" / "planar.*.so")):
        pytest.skip("the ECU core is not compiled here (CRD_PURE_PYTHON=1 or a failed build): nothing to compare")
    source = tmp_path / "source"
    shutil.copytree(ECU_DIR, source / "ecu", ignore=shutil.ignore_patterns("*.so", "__pycache__"))
    compiled, where_compiled = _run(tmp_path, None)
    pure, where_pure = _run(tmp_path, str(source))
    assert ".so" in where_compiled and str(source) in where_pure  # each ran the core it should
    assert compiled.count("\n") == 4 and compiled == pure
