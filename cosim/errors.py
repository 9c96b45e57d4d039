"""Typed errors of the co-simulation.

::

    ConfigError (ValueError)                        bad scenario file: names the key path and the file
                                                    (crd's one configuration error, from can_dbc.errors)
    CosimError (Exception)
     +-- PlantError (CosimError, RuntimeError)      FMU missing, broken or mis-mapped
     |    +-- MappingError (PlantError, KeyError)   a mapped name the FMU lacks / wrong causality
     |    +-- FmiStepError (PlantError)             FMU returned an error mid-run (time + status)
"""

from __future__ import annotations

from can_dbc.errors import ConfigError

__all__ = ["ConfigError", "CosimError", "FmiStepError", "MappingError", "PlantError"]


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
