"""A compiled core module older than its source is refused, naming it and the fix (ecu/compiled_core.py)."""

import os
import shutil
from pathlib import Path

import pytest

from ecu import compiled_core


def _touch(path, mtime):
    path.write_text("")
    os.utime(path, (mtime, mtime))


def test_a_source_newer_than_its_compiled_module_is_refused_with_its_name(tmp_path):
    _touch(tmp_path / "plan.cpython-311-x86_64-linux-gnu.so", 1000.0)
    _touch(tmp_path / "plan.py", 1000.0 + compiled_core.TOLERANCE_S + 1.0)
    _touch(tmp_path / "step.cpython-311-x86_64-linux-gnu.so", 1000.0)
    _touch(tmp_path / "step.py", 1000.0 + compiled_core.TOLERANCE_S / 2)  # written by the same install
    _touch(tmp_path / "_compiled__mypyc.cpython-311-x86_64-linux-gnu.so", 1.0)  # the group's runtime: no source
    assert compiled_core.stale_modules(str(tmp_path)) == ["plan"]
    with pytest.raises(ImportError, match=r"^ecu/core/plan\.py: newer than the compiled core .*pip install -e \."):
        compiled_core.check(str(tmp_path))


def test_a_stale_region_module_is_named_by_its_path(tmp_path):
    (tmp_path / "region").mkdir()
    _touch(tmp_path / "region" / "decision.cpython-311-x86_64-linux-gnu.so", 1000.0)
    _touch(tmp_path / "region" / "decision.py", 1000.0 + compiled_core.TOLERANCE_S + 1.0)
    _touch(tmp_path / "region" / "_compiled__mypyc.cpython-311-x86_64-linux-gnu.so", 1.0)
    with pytest.raises(ImportError, match=r"^ecu/core/region/decision\.py: newer than the compiled core"):
        compiled_core.check(str(tmp_path))


def test_the_installed_core_is_not_stale():
    assert compiled_core.stale_modules() == []


def test_the_core_is_compiled_where_a_c_compiler_is():
    """A mypyc error does not fail the install (setup.py prints "stays pure Python" and goes on), so without this
    test a core that no longer compiles would pass every other test in Python, slower (round 33: one missing
    annotation in ecu/core/steering.py did just that)."""
    if os.environ.get("CRD_PURE_PYTHON"):
        pytest.skip("CRD_PURE_PYTHON is set: the core is Python by request")
    if not (shutil.which("cc") or shutil.which("gcc")):
        pytest.skip("no C compiler here: setup.py installs the core as Python, as documented")
    core = Path(compiled_core.__file__).resolve().parent / "core"
    missing = [group for group in (core, core / "region") if not list(group.glob("_compiled__mypyc.*.so"))]
    assert not missing, f"not compiled: {[str(g) for g in missing]}; see the mypyc errors of `pip install -v -e .`"
