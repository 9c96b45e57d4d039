import pytest

from fmu_plant.build import ensure_fmu


@pytest.fixture(scope="session")
def plant_fmu3():
    return ensure_fmu(fmi_version=3)
