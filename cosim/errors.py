"""Typed errors of the co-simulation.

::

    ConfigError (ValueError)                        bad configuration file: names the file and the key path
     |                                              (crd's one configuration error, from can_dbc.errors)
     +-- SettingError (ConfigError)                 from the one loader (ecu.settings): ``<key.path>: <problem>``
    CosimError (Exception)
     +-- PlantError (CosimError, RuntimeError)      FMU missing, broken or mis-mapped
     |    +-- MappingError (PlantError, KeyError)   a mapped name the FMU lacks / wrong causality
     |    +-- FmiStepError (PlantError)             FMU returned an error mid-run (time + status)
     +-- EcuStallError (CosimError, RuntimeError)  lock-step: the ECU did not answer within the stall limit
     +-- EcuSettingsError (CosimError, ValueError) an attached ECU announces other settings than the run's
                                                    [ecu], or none (cosim.link.ecu_identity)
    RunInterrupted (KeyboardInterrupt)             SIGINT or SIGTERM asked the run to stop
"""

from __future__ import annotations

import signal

from can_dbc.errors import ConfigError

__all__ = ["ConfigError", "CosimError", "EcuStallError", "FmiStepError", "MappingError", "PlantError",
           "RunInterrupted"]


class CosimError(Exception):
    """Base of every co-simulation error."""


class PlantError(CosimError, RuntimeError):
    """The plant FMU cannot be loaded, instantiated or stepped."""


class MappingError(PlantError, KeyError):
    """A ``[plant.inputs]``/``[plant.outputs]`` name does not match the FMU."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class FmiStepError(PlantError):
    """The FMU returned an error status during the run.

    ``time_s`` is the communication point at which it failed and ``status`` the
    FMI status name (for example ``"fmi3Error"``).
    """

    def __init__(self, message: str, time_s: float, status: str) -> None:
        super().__init__(message)
        self.time_s = time_s
        self.status = status


class EcuStallError(CosimError, RuntimeError):
    """Lock-step: the ECU did not answer a cycle within the stall limit; the run stops at ``time_s``."""

    def __init__(self, message: str, time_s: float) -> None:
        super().__init__(message)
        self.time_s = time_s


class RunInterrupted(KeyboardInterrupt):
    """A signal (``signum``: SIGINT or SIGTERM) asked the run to stop; results so far are kept.

    A ``KeyboardInterrupt`` so that everything that already stops on Ctrl-C stops on it too.
    """

    def __init__(self, signum: int, message: str = "") -> None:
        super().__init__(message or f"interrupted by {signal_name(signum)}")
        self.signum = signum


def signal_name(signum: int) -> str:
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


def interrupt_signal(exc: KeyboardInterrupt) -> int:
    """The signal behind ``exc``: its own for :class:`RunInterrupted`, SIGINT for a plain Ctrl-C."""
    return exc.signum if isinstance(exc, RunInterrupted) else int(signal.SIGINT)
