"""Collision-avoidance strategies: one module each, in one registry.

A strategy (Johnson 2019, section III; ``adaptive`` is our extension) decides,
each cycle, what :class:`ecu.core.strategy.Strategy` lists: the model
deceleration D its stopping paths plan with, and whether and how it tightens
the driver's acceleration bound. The paper's three: ``none`` and
``conservative`` differ only in D (0.9 and 0.8 of the peak); ``tightening``
plans with 0.9 and tightens. ``adaptive`` is ``tightening`` with D from an
online estimate (:mod:`ecu.core.decel_estimate`).

**Adding one** is its module here, named as its ``EcuStatus.Strategy``
``VAL_`` entry in lower case, with a module-level ``STRATEGY`` that satisfies
:class:`~ecu.core.strategy.Strategy`, and its value in that ``VAL_`` line of
the DBC. :data:`REGISTRY` finds the module by a scan of this package (modules
named ``_*`` are not strategies); the command lines, the configuration and
``EcuStatus`` take the name from the DBC. The two must agree: a module without
its ``VAL_`` entry, or an entry without its module, stops the import with an
error naming it.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Mapping

from can_dbc import DBC_PATH
from can_dbc.contract import STRATEGY_CODES

from ..strategy import Strategy


def _registry() -> dict[str, Strategy]:
    """Every module of this package (not ``_private``) by name, in the DBC's value order; checked against it."""
    modules = {info.name for info in pkgutil.iter_modules(__path__) if not info.name.startswith("_")}
    unlisted = sorted(modules - set(STRATEGY_CODES))
    if unlisted:
        raise ImportError(f"ecu/core/strategies: expected a VAL_ entry of EcuStatus.Strategy in {DBC_PATH} "
                          f"for every module, got none for {unlisted}")
    missing = [f"{code} {name.upper()!r}" for name, code in STRATEGY_CODES.items() if name not in modules]
    if missing:
        raise ImportError(f"{DBC_PATH}: expected a module in ecu/core/strategies for every VAL_ entry of "
                          f"EcuStatus.Strategy, got none for {missing}")
    registry = {name: getattr(importlib.import_module(f"{__name__}.{name}"), "STRATEGY", None)
                for name in STRATEGY_CODES}
    for name, strategy in registry.items():
        if not isinstance(strategy, Strategy):
            raise ImportError(f"ecu/core/strategies/{name}.py: expected STRATEGY satisfying "
                              f"ecu.core.strategy.Strategy, got {strategy!r}")
    return registry


#: strategy name -> its rules, in the order of the DBC's ``EcuStatus.Strategy`` values
REGISTRY: Mapping[str, Strategy] = _registry()
