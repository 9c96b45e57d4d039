"""The ECU's configuration for one run: the scenario's ``[ecu]``, the strategy and the scene's equipment."""

from __future__ import annotations

import dataclasses

from ecu import EcuConfig

from ..scenarios.config import Scenario


def ecu_config(scenario: Scenario, strategy: str | None = None) -> EcuConfig:
    """The scenario's ``[ecu]`` (an :class:`ecu.EcuConfig`, checked at load), ``strategy`` in place of its own,
    with the equipment the scene gives (``Scenario.equipment``: which frames the run's bus carries). Steering
    authority is the equipment's (``planar_steering``: a planar scene whose plant takes the ECU's steering,
    ``[plant.inputs] steer_request``, as the builtin plant does; :class:`ecu.EcuConfig`)."""
    changes: dict[str, object] = {}
    if strategy is not None and strategy != scenario.ecu.strategy:
        changes["strategy"] = strategy
    if scenario.ecu.equipment != scenario.equipment:
        changes["equipment"] = scenario.equipment  # and with it steering authority (ecu.EcuConfig)
    return dataclasses.replace(scenario.ecu, **changes) if changes else scenario.ecu
