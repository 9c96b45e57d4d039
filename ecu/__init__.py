"""The active-safety ECU: a pure core and a thin CAN node shell.

``ecu.core`` holds the logic (``step(state, inputs, params)``; no I/O);
``ecu.node.EcuNode`` runs it on any ``can.BusABC`` in lock-step
(``step(t_s)``), real time or sim time (``run(stop_event)``);
``ecu.config.EcuConfig`` is its frozen configuration; ``crd ecu`` its CLI.
"""

from .config import ECU_CYCLE_S, EcuConfig
from .errors import ConfigError
from .node import EcuNode
from .scheduler import Percentiles, RunReport

__all__ = ["ECU_CYCLE_S", "ConfigError", "EcuConfig", "EcuNode", "Percentiles", "RunReport"]
