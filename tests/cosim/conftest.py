"""Shared fixtures: the builtin plant FMUs and the pythonfmu fixture FMU (built once per session)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="session")
def plant_fmu3() -> Path:
    from fmu_plant.build import ensure_fmu

    return Path(ensure_fmu(fmi_version=3))


@pytest.fixture(scope="session")
def point_mass_fmu(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("fixture_fmu")
    subprocess.run([sys.executable, "-m", "pythonfmu", "build", "-f", str(HERE / "point_mass_slave.py"),
                    "-d", str(out)], check=True, capture_output=True)
    return out / "PointMass.fmu"
