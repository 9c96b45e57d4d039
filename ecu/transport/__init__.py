"""Cross-process loopback CAN transport: ``UnixSocketBus`` and its broadcast ``Hub``.

Registered with python-can as interface ``crd_unix``:
``can.Bus(interface="crd_unix", channel="/tmp/crd-can0.sock")``. See README.md.
Names are imported lazily so that ``python -m ecu.transport.hub`` runs cleanly.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["Hub", "UnixSocketBus"]

_WHERE = {"Hub": "ecu.transport.hub", "UnixSocketBus": "ecu.transport.unix_bus"}


def __getattr__(name: str) -> Any:
    if name not in _WHERE:
        raise AttributeError(f"module 'ecu.transport' has no attribute {name!r}")
    return getattr(importlib.import_module(_WHERE[name]), name)
