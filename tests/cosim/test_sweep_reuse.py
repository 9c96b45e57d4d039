"""A sweep worker prepares the plant FMU once (``share_fmu``): runs on it equal runs on a fresh load, bit for bit.

The shared FMU keeps one extraction, one model description and one loaded library; each run
instantiates and frees its own instance. Runs with different plant parameters alternate, so an
instance that inherited anything from the previous one would show. About 3 s.
"""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import pytest

from cosim.errors import PlantError
from cosim.loop.master import run_scenario
from cosim.scenarios.loader import load_scenario
from cosim.world.fmu_share import share_fmu, unshare_fmu
from cosim.world.plant_fmu import FmuPlant

BASE = Path(__file__).resolve().parent / "sweep_data" / "short_cyclist.toml"


def _variant(friction: float, dead_time_s: float):
    sc = load_scenario(BASE)
    plant = dataclasses.replace(sc.plant, road_friction=friction,
                                parameters={**sc.plant.parameters, "brake_dead_time": dead_time_s})
    return dataclasses.replace(sc, plant=plant)


def _result(scenario, fmu: Path):
    record = run_scenario(scenario, fmu)
    return record.rows, dataclasses.replace(record.metrics, wall_time_s=0.0), record.error


@pytest.fixture(params=[3, 2], ids=["fmi3", "fmi2"])
def fmu_copy(request, tmp_path) -> Path:
    """A private copy of the builtin plant (FMI 3 or 2), so sharing it touches no other test."""
    from fmu_plant.build import ensure_fmu

    path = tmp_path / f"plant{request.param}.fmu"
    shutil.copyfile(ensure_fmu(fmi_version=request.param), path)
    yield path
    unshare_fmu(path)


def test_runs_on_a_shared_fmu_equal_runs_on_a_fresh_load(fmu_copy) -> None:
    scenarios = [_variant(1.0, 0.10), _variant(0.5, 0.20), _variant(1.0, 0.10)]
    fresh = [_result(sc, fmu_copy) for sc in scenarios[:2]]
    shared = share_fmu(fmu_copy)
    reused = [_result(sc, fmu_copy) for sc in scenarios]
    assert shared.slave is not None and not shared.busy
    handle = shared.slave.dll._handle
    assert reused[0] == fresh[0] and reused[1] == fresh[1] and reused[2] == fresh[0]
    assert fresh[0] != fresh[1]  # the variants differ, so equality above says something
    assert _result(scenarios[1], fmu_copy) == fresh[1] and shared.slave.dll._handle == handle  # same library
    with pytest.raises(PlantError, match="refused initialisation"):  # brake_dead_time out of the FMU's range
        _result(_variant(1.0, 0.9), fmu_copy)
    assert _result(scenarios[0], fmu_copy) == fresh[0] and not shared.busy  # a refused instance leaves no trace


def test_a_second_plant_at_once_loads_its_own_copy(fmu_copy) -> None:
    sc = _variant(1.0, 0.10)
    shared = share_fmu(fmu_copy)
    with FmuPlant(sc.plant, fmu_copy) as first:
        assert shared.busy
        with FmuPlant(sc.plant, fmu_copy) as second:
            assert second._fmu is not shared.slave and first._fmu is shared.slave
            for plant in (first, second):
                plant.set_actuation(0.5, 0.0)
                plant.step(0.0, 0.001)
            assert first.read() == second.read()
    assert not shared.busy


def test_fmu_shared_prepares_once_for_the_block_and_cleans_up(fmu_copy) -> None:
    """crd paper's parent prepares the FMU once before it forks its run workers (fmu_shared)."""
    from cosim.world.fmu_share import SHARED, fmu_shared

    with fmu_shared(fmu_copy) as shared:
        extraction = Path(shared.unzipdir)
        assert SHARED[fmu_copy] is shared and extraction.is_dir()
        assert _result(_variant(1.0, 0.10), fmu_copy)[2] is None and shared.slave is not None
    assert fmu_copy not in SHARED and not extraction.exists()  # unshared: library unloaded, extraction gone
    before = share_fmu(fmu_copy)  # shared by someone else before the block: left shared after it
    with fmu_shared(fmu_copy) as shared:
        assert shared is before
    assert SHARED[fmu_copy] is before and Path(before.unzipdir).is_dir()
