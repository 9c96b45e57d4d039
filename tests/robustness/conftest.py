"""The faulty fixture FMU, built once per session with pythonfmu."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="session")
def faulty_fmu(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("faulty_fmu")
    subprocess.run([sys.executable, "-m", "pythonfmu", "build", "-f", str(HERE / "faulty_slave.py"),
                    "-d", str(out)], check=True, capture_output=True)
    return out / "Faulty.fmu"


@pytest.fixture(scope="session")
def plant_fmu3() -> Path:
    from fmu_plant.build import ensure_fmu

    return Path(ensure_fmu(fmi_version=3))
