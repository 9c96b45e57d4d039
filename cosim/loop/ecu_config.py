"""The ECU's configuration for one run: the scenario's ``[ecu]``, the strategy, and steering authority."""

from __future__ import annotations

import dataclasses

from ecu import EcuConfig

from ..scenarios.config import Scenario


def ecu_config(scenario: Scenario, strategy: str | None = None) -> EcuConfig:
    """The scenario's ``[ecu]`` (an :class:`ecu.EcuConfig`, checked at load), ``strategy`` in place of its own, and
    steering authority granted when the run's plant takes the ECU's steering (``[plant.inputs] steer_request``: a
    planar scenario with the builtin plant, or a plant that maps it)."""
    changes: dict[str, object] = {}
    if strategy is not None and strategy != scenario.ecu.strategy:
        changes["strategy"] = strategy
    if scenario.plant.input_map("steer_request") is not None and not scenario.ecu.steering_authority:
        changes["steering_authority"] = True
    return dataclasses.replace(scenario.ecu, **changes) if changes else scenario.ecu
