"""The faulty fixture FMU, built once per session with pythonfmu."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.os_processes import build_pythonfmu

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="session")
def faulty_fmu(tmp_path_factory) -> Path:
    return build_pythonfmu(HERE / "faulty_slave.py", tmp_path_factory.mktemp("faulty_fmu"), "Faulty")


@pytest.fixture(scope="session")
def plant_fmu3() -> Path:
    from fmu_plant.build import ensure_fmu

    return Path(ensure_fmu(fmi_version=3))
