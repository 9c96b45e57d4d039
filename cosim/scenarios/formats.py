"""Scenario files by suffix: a table from suffix to reader (``.toml`` crd's own, ``.xosc`` OpenSCENARIO).

``read_scenario(path, ego)``: ``ego`` names the equipped car of an
OpenSCENARIO file (default the entity named Ego/hero); a TOML scenario has one
ego and refuses the option.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from ..errors import ConfigError
from .config import Scenario
from .loader import load_scenario


def _toml(path: Path, ego: str | None) -> Scenario:
    if ego is not None:
        raise ConfigError(f"{path}: --ego names an entity of an OpenSCENARIO file; a TOML scenario has one ego")
    return load_scenario(path)


def _xosc(path: Path, ego: str | None) -> Scenario:
    from .openscenario import read_xosc  # lxml: the xosc extra, loaded only for .xosc files

    return read_xosc(path, ego)


READERS: dict[str, Callable[[Path, str | None], Scenario]] = {".toml": _toml, ".xosc": _xosc}


def read_scenario(path: str | Path, ego: str | None = None) -> Scenario:
    """The scenario in ``path``, read by its suffix."""
    path = Path(path)
    reader = READERS.get(path.suffix.lower())
    if reader is None:
        raise ConfigError(f"{path}: unknown scenario format {path.suffix!r}; expected one of {', '.join(READERS)}")
    return reader(path, ego)
