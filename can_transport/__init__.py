"""python-can interfaces of our own: the in-process ``InProcessBus`` and the cross-process
loopback transports ``UnixSocketBus`` (with its broadcast ``Hub``) and ``PairSocketBus``.

Registered with python-can as interfaces ``crd_inproc`` (in process, no copies),
``crd_unix`` (any number of participants, through a hub) and ``crd_pair`` (exactly
two, point to point, for lock-step round trips): ``can.Bus(interface="crd_unix", channel="/tmp/crd-can0.sock")``.
See README.md.
Names are imported lazily so that ``python -m can_transport.hub`` runs cleanly.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["Hub", "InProcessBus", "PairSocketBus", "UnixSocketBus"]

_WHERE = {"Hub": "can_transport.hub", "InProcessBus": "can_transport.inproc_bus",
          "PairSocketBus": "can_transport.pair_bus",
          "UnixSocketBus": "can_transport.unix_bus"}


def __getattr__(name: str) -> Any:
    if name not in _WHERE:
        raise AttributeError(f"module 'can_transport' has no attribute {name!r}")
    return getattr(importlib.import_module(_WHERE[name]), name)
