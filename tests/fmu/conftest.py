"""Build each FMU once per test session (cached by source hash in fmu_plant/_build/)."""

from pathlib import Path

import pytest

from fmu_plant.build import ensure_fmu


@pytest.fixture(scope="session")
def fmus() -> dict[int, Path]:
    return {2: ensure_fmu(fmi_version=2), 3: ensure_fmu(fmi_version=3)}


@pytest.fixture(scope="session")
def fmu2(fmus) -> Path:
    return fmus[2]
