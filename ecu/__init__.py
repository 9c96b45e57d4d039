"""The active-safety ECU: a pure core and a thin CAN node shell.

``ecu.core`` holds the logic (``step(state, inputs, params)``; no I/O);
``ecu.node.EcuNode`` runs it on any ``can.BusABC`` in lock-step
(``step(t_s)``), real time or sim time (``run(stop_event)``);
``ecu.config.EcuConfig`` is its frozen configuration; ``crd ecu`` its CLI,
and ``python -m ecu`` the same command as a program of its own (how the
co-simulation spawns it, see :mod:`ecu.__main__`).

The names below are imported on first use (PEP 562), not with the package:
``python -m ecu`` must run its own start-up (:mod:`ecu.__main__`) before
python-can is imported, and importing the package alone imports nothing else.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from . import compiled_core

compiled_core.check()  # a compiled ECU core older than its sources would run old code

#: public name -> submodule that defines it
_EXPORTS = {
    "ECU_CYCLE_S": "config",
    "EcuConfig": "config",
    "ConfigError": "errors",
    "EcuNode": "node",
    "Percentiles": "scheduler",
    "RunReport": "scheduler",
}

__all__ = sorted(_EXPORTS)

if TYPE_CHECKING:
    from .config import ECU_CYCLE_S, EcuConfig
    from .errors import ConfigError
    from .node import EcuNode
    from .scheduler import Percentiles, RunReport


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'ecu' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value  # once: later look-ups find it without this hook
    return value


def __dir__() -> list[str]:
    return sorted([*globals(), *_EXPORTS])
