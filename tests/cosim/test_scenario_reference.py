"""docs/scenario-reference.md is rendered from the declarations and cannot drift from them."""

from __future__ import annotations

from pathlib import Path

from cosim.scenarios.config import Scenario
from cosim.scenarios.reference import COMMAND, render
from cosim.scenarios.planar_config import SteeringConfig
from cosim.world.driver_models import DRIVER_MODELS
from cosim.world.steering_models import STEERING_MODELS
from ecu.settings import keys, walk

PAGE = Path(__file__).resolve().parents[2] / "docs" / "scenario-reference.md"


def test_committed_page_is_a_fresh_render():
    assert PAGE.read_text() == render(), f"docs/scenario-reference.md is stale: run `{COMMAND}`"


def test_page_names_every_key_driver_model_and_the_reference_point():
    page = render()
    for path, key in walk(Scenario):
        if "." in path:  # a key of a section (sections are headings)
            assert f"| `{key.name}` |" in page, path
    for name in keys(Scenario):
        assert f"## `[{name}]`" in page or f"## `[[{name}]]`" in page, name
    for model in DRIVER_MODELS:
        assert f"### `{model}`" in page, model
    assert "position of its **rear** at\nt = 0, is the initial gap between the ego's front bumper" in page
    declared = keys(Scenario)["driver"].hint
    assert set(keys(declared)["model"].declared.choices) == set(DRIVER_MODELS)  # the choices are the registry's


def test_steering_model_choices_are_the_registry():
    """`[driver.steering] model` declares its choices where the key is declared (the world imports the
    configuration, not the other way round); this keeps them equal to the steering-model registry."""
    assert set(keys(SteeringConfig)["model"].declared.choices) == set(STEERING_MODELS)
    for model in STEERING_MODELS:
        assert f"`{model}`" in PAGE.read_text(), model
