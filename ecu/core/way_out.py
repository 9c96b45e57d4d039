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

**Backing off.** Two patiences closer than the time to see the other start send both cars at once. At a
narrowing each then meets the other on the move while taking its turn (*contested*,
:class:`ecu.core.region.narrowing.Turn`): both give the turn back, count their patience anew, and from then on
yield to any car on the move toward the narrowing until they have passed it. The new wait is a seeded uniform
fraction of the car's patience, drawn afresh at every back-off from ``way_out_seed`` and the number of back-offs
(Python's :class:`random.Random`, seeded with a string, as the fleet draws the patience): the random backoff of
CSMA/CD (IEEE 802.3's truncated binary exponential backoff draws a uniform number of slot times), with one
window, the car's own patience, so that the retries stay short. Two draws meet again with a probability of
about twice the detection time over the patience (0.4 s over 0.5-3 s), and a new draw follows.
"""

from __future__ import annotations

import functools
import math
import random

from .params import CoreParams
from .planar import RegionCycle, held_back
from .region.narrowing import Turn
from .types import CoreState


@functools.lru_cache(maxsize=64)
def backoff_fraction(seed: int, backoffs: int) -> float:
    """The seeded uniform draw in [0, 1) of back-off number ``backoffs`` (module docstring); a pure function, kept
    for the cycles that read it while the car waits (seeding the generator costs 6 us a call)."""
    return random.Random(f"way-out backoff/{seed}/{backoffs}").random()


def patience_s(state: CoreState, params: CoreParams) -> float:
    """The wait before the car takes its turn: its patience, or after a back-off a fresh fraction of it."""
    if state.way_out_backoffs == 0:
        return params.way_out_patience_s
    return params.way_out_patience_s * backoff_fraction(params.way_out_seed, state.way_out_backoffs)


def impatient(state: CoreState, params: CoreParams) -> bool:
    """The car has waited its patience out (only with a way-out rule)."""
    return params.way_out != "none" and state.slow_cycles * params.cycle_s >= patience_s(state, params) - 1e-9


def turn(state: CoreState, params: CoreParams) -> Turn:
    """Where the car stands in its patience (:class:`ecu.core.region.narrowing.Turn`)."""
    if impatient(state, params):
        return Turn.TAKING
    return Turn.BACKED_OFF if state.way_out_backoffs else Turn.NONE


def next_slow_cycles(state: CoreState, speed_mps: float, near: bool, params: CoreParams) -> int:
    """Cycles slow while ``near`` (held back, or impatient already), counted on; 0 once going or not ``near``."""
    if params.way_out == "none" or speed_mps >= params.way_out_slow_speed_mps or not near:
        return 0
    return min(state.slow_cycles + 1, math.ceil(params.way_out_patience_s / params.cycle_s) + 1)


def next_way_out(state: CoreState, speed_mps: float, region: RegionCycle | None, taking: bool,
                 params: CoreParams) -> tuple[int, int]:
    """(slow cycles, back-offs) of the next cycle: a contested turn backs off (the count starts again, one more
    back-off); the back-offs are forgotten once the car is going with no narrowing ahead (module docstring;
    not while slow: braking hard, the radar's lagging relative speeds make parked cars seem to move, and the
    narrowing drops out of sight for a few cycles)."""
    if taking and region is not None and region.contested:
        return 0, state.way_out_backoffs + 1
    ahead = region is not None and region.at_narrowing
    backoffs = state.way_out_backoffs if ahead or speed_mps < params.way_out_slow_speed_mps else 0
    return next_slow_cycles(state, speed_mps, taking or held_back(region), params), backoffs
