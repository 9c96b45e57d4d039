"""The seeded asymmetric release of ``[ecu] way_out = "right_of_way"`` (issue 23's way out of a deadlock).

Giving way to the right (:data:`ecu.core.region.crossing.WAY_OUT_RULES`) resolves two cars at a crossing: one
of them has the other on its right and yields, the other does not. At a four-way crossing each car has one on
its right, every car yields, and they dance or stand (traffic law leaves that case to the drivers). The tie is
broken by **patience**: a car that has been slow (below ``way_out_slow_speed_mps``) for
``way_out_patience_s`` while held back (something near its nominal path, the region's proximity above 0, or a
standoff at a two-sided narrowing, :func:`ecu.core.planar.held_back`) stops giving way and takes its turn; it
stays impatient while it is slow, and gives way again once it is going (above the slow speed). Each car's ECU
has its own patience (a fleet draws it per car from its seed, :mod:`cosim.fleet.config`), so the cars do not
all lose patience at once. Only tightening is given up: the contingency keeps the car's stopping path
disjoint from every object's stopping region, so the car that takes its turn still stops for a car that
goes at the same time.
"""

from __future__ import annotations

import math

from .params import CoreParams
from .types import CoreState


def impatient(state: CoreState, params: CoreParams) -> bool:
    """The car has waited its patience out (only with a way-out rule)."""
    return params.way_out != "none" and state.slow_cycles * params.cycle_s >= params.way_out_patience_s - 1e-9


def next_slow_cycles(state: CoreState, speed_mps: float, near: bool, params: CoreParams) -> int:
    """Cycles slow while ``near`` (held back, or impatient already), counted on; 0 once going or not ``near``."""
    if params.way_out == "none" or speed_mps >= params.way_out_slow_speed_mps or not near:
        return 0
    return min(state.slow_cycles + 1, math.ceil(params.way_out_patience_s / params.cycle_s) + 1)
