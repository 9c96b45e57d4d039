"""Shared fixtures: the builtin plant FMUs and the pythonfmu fixture FMU (built once per session)."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.os_processes import build_pythonfmu

HERE = Path(__file__).resolve().parent


@pytest.fixture(scope="session")
def plant_fmu3() -> Path:
    from fmu_plant.build import ensure_fmu

    return Path(ensure_fmu(fmi_version=3))


@pytest.fixture(scope="session")
def point_mass_fmu(tmp_path_factory) -> Path:
    return build_pythonfmu(HERE / "point_mass_slave.py", tmp_path_factory.mktemp("fixture_fmu"), "PointMass")


@pytest.fixture(scope="session")
def st_vehicle_fmu(tmp_path_factory) -> Path:
    """CommonRoad's ST model as a third-party planar FMU (tests/cosim/st_vehicle_slave.py)."""
    return build_pythonfmu(HERE / "st_vehicle_slave.py", tmp_path_factory.mktemp("st_fmu"), "StVehicle")
