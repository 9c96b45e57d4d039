"""A compiled ECU core older than its sources is refused at import (``setup.py`` compiles ``ecu/core`` with mypyc).

Python loads ``ecu/core/<name>.cpython-*.so`` before ``<name>.py``: after an edit of a compiled
module's source, or a checkout that changes it, the core would run the old code without a word.
:func:`check` (called by ``import ecu``) raises :class:`StaleCompiledCore`, naming the modules and
the fix, when a source is newer than its compiled module by more than :data:`TOLERANCE_S` (an
install writes both within it).
"""

from __future__ import annotations

import os

CORE_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "core")
#: how much newer a source may be than its compiled module (s): an install writes both within it
TOLERANCE_S = 2.0


class StaleCompiledCore(ImportError):
    """A compiled core module is older than its source."""


def stale_modules(core_dir: str = CORE_DIR) -> list[str]:
    """The compiled core modules (``ecu/core`` and its ``region``) whose source is newer (by more than
    :data:`TOLERANCE_S`), as paths under ``core_dir`` without ``.py``."""
    stale = []
    for folder, prefix in ((core_dir, ""), (os.path.join(core_dir, "region"), "region/")):
        if not os.path.isdir(folder):
            continue
        for entry in os.scandir(folder):
            name, _, suffix = entry.name.partition(".")
            if not suffix.endswith(".so") or name.startswith("_compiled"):
                continue
            source = os.path.join(folder, f"{name}.py")
            if os.path.exists(source) and os.stat(source).st_mtime > entry.stat().st_mtime + TOLERANCE_S:
                stale.append(prefix + name)
    return sorted(stale)


def check(core_dir: str = CORE_DIR) -> None:
    """Raise :class:`StaleCompiledCore` if a compiled core module is older than its source."""
    stale = stale_modules(core_dir)
    if stale:
        names = ", ".join(f"ecu/core/{name}.py" for name in stale)
        raise StaleCompiledCore(f"{names}: newer than the compiled core (setup.py, mypyc); run pip install -e . "
                                f"again, or delete ecu/core/*.so and ecu/core/region/*.so to run the sources")
