"""One doStep per ECU cycle for an FMU with a fixed internal step gives the same run as h-sized steps."""

import pytest

from can_dbc import generate_key, write_key_file
from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import ClosedLoop
from cosim.world.plant import divides_step
from cosim.scenarios.loader import load_scenario


@pytest.fixture(scope="module")
def key_file(tmp_path_factory):
    """One SecOC key for both runs, so that their authenticator frames agree too."""
    return str(write_key_file(tmp_path_factory.mktemp("key") / "run.key", generate_key()))


def _run(fmu, strategy: str, batch: bool, key_file: str):
    loop = ClosedLoop(load_scenario(PAPER_SCENARIO), fmu, strategy, batch_steps=batch,
                      ecu=EcuOptions(key_file=key_file))
    assert loop.batch_steps is batch
    return loop.run()


@pytest.mark.parametrize("strategy", ["none", "tightening"])  # a collision, and a stop short
def test_batched_steps_give_the_same_run(plant_fmu3, strategy, key_file):
    batched, single = _run(plant_fmu3, strategy, True, key_file), _run(plant_fmu3, strategy, False, key_file)
    a, b = batched.metrics.as_dict(), single.metrics.as_dict()
    a.pop("wall_time_s"), b.pop("wall_time_s")
    assert a == b
    assert batched.rows == single.rows and batched.frames == single.frames
    assert batched.events == single.events


def test_only_an_fmu_declaring_a_fixed_internal_step_is_batched():
    from fmu_plant.build import ensure_fmu

    from cosim.world.plant_fmu import FmuPlant

    scenario = load_scenario(PAPER_SCENARIO)
    with FmuPlant(scenario.plant, ensure_fmu(fmi_version=3)) as fmi3, \
         FmuPlant(scenario.plant, ensure_fmu(fmi_version=2)) as fmi2:
        assert fmi3.fixed_internal_step_s == 1e-3
        assert fmi2.fixed_internal_step_s is None  # FMI 2 has no such attribute


@pytest.mark.parametrize(("internal", "h", "expected"), [
    (1e-3, 1e-3, True), (1e-3, 2e-3, True), (1e-3, 5e-4, False), (1e-3, 1.5e-3, False), (None, 1e-3, False),
])
def test_divides(internal, h, expected):
    assert divides_step(internal, h) is expected
