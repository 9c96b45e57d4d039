"""The written-out core step equals the step composed from the documented functions, bit for bit.

:func:`ecu.core.step` inlines the small functions of ``ecu.core`` for speed
(issue 10); ``reference_step`` composes them. Both run side by side over
seeded random drives (approach, braking, moving and oncoming objects, objects
beside the path) with inputs that are, at a per-run rate, timed out, stamped
in the future, E2E-invalid, flagged by the receiver, implausible or not
finite, for every strategy and a few parameter variants; every state and
output must be identical (floats compared by ``repr``, so NaN and -0.0 count).
Also the public :func:`ecu.core.plan_cycle` against the reference's. ~2 s.
"""

from __future__ import annotations

import math
import random

import pytest

from ecu.core import CoreInputs, CoreParams, CoreState, plan_cycle, step
from ecu.core.types import Mode

from . import reference_step as ref

_ODD = (math.nan, math.inf, -math.inf, -1.0, 0.0, 1e300, 2.0)
_VARIANTS = ({}, {"driven_axle": "rear"}, {"driven_axle": "all"},
             {"contingency_release_ratio": 1.3, "contingency_release_speed_mps": 0.5})


def _exact(value: object) -> object:
    """A value comparable bit for bit: floats by repr (NaN equals NaN, -0.0 differs from 0.0), types kept."""
    if isinstance(value, tuple):
        return (type(value).__name__, tuple(_exact(v) for v in value))
    if isinstance(value, float):
        return repr(value)
    return (type(value).__name__, value)


def _inputs(rng: random.Random, t_s: float, speed_mps: float, range_m: float, rate_mps: float,
            noise: float) -> CoreInputs:
    def odd(good, bad):
        return rng.choice(bad) if rng.random() < noise else good

    wheels = tuple(odd(max(0.0, speed_mps + rng.gauss(0.0, 0.1)), _ODD) for _ in range(4))
    if rng.random() < 5 * noise:  # locked or spinning wheels
        wheels = tuple(speed_mps * rng.uniform(0.3, 1.5) for _ in range(4))
    elif rng.random() < 0.02:  # a spread at the slip bound (2 m/s + 30 % of the fastest wheel, the defaults),
        top = speed_mps + 1.0 + 0.1 * speed_mps  # the mean rising: not braking, so the bound is checked
        wheels = (top, top, max(0.0, 0.7 * top - 2.0 + rng.choice((-0.005, 0.0, 0.005))), top)
    brake = rng.choice((0.0,) * 30 + (1.0, rng.random(), 0.6))
    accel = rng.choice((0.0, 1.0, 1.0, 1.0, 0.3, rng.random())) if brake <= 0.5 else odd(0.0, (0.6, 1.0))
    rx = (lambda: t_s - odd(0.0, (0.01, 0.04, 0.06, 0.3, 1.0, -0.01, math.inf)))
    return CoreInputs(
        t_s, wheels, odd(accel, (0.6, -0.1, 1.1, math.nan)), brake, rng.random() < 0.9,
        odd(max(0.0, range_m + rng.gauss(0.0, 0.2)), _ODD), odd(rate_mps + rng.gauss(0.0, 0.2), _ODD),
        rx(), rx(), rx(), odd(0, (1, 4, 5, 6)), odd(0, (5,)), odd(0, (5,)),
        rng.choice((0.0,) * 10 + (0.5, 1.9, 2.0, 3.5, -1.0, odd(0.0, (math.nan,)))),
        odd(0, (32, 4096)), odd(0, (32,)), odd(0, (32, 4096)), odd(0, (512, 1024, 2048)))


@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening", "adaptive"])
@pytest.mark.parametrize("noise", [0.0, 0.0005, 0.003, 0.02])
def test_step_equals_the_composed_reference(strategy: str, noise: float) -> None:
    rng = random.Random(f"{strategy}/{noise}")
    modes = set()
    for variant in _VARIANTS:
        params = CoreParams(strategy=strategy, **variant)
        state = expected_state = CoreState()
        speed, range_m, object_mps = rng.uniform(0, 30), rng.uniform(0, 80), rng.choice((0.0, 5.0, -5.0, 20.0))
        for k in range(600):
            speed = max(0.0, speed + rng.choice((3.0, -9.0, 0.0, -3.0)) * 0.03 * rng.random())
            range_m -= (speed - object_mps) * 0.01
            if range_m < 0.0 or rng.random() < 0.005:
                range_m, speed = rng.uniform(0, 80), rng.uniform(0, 30)
            inputs = _inputs(rng, k * 0.01, speed, range_m, object_mps - speed, noise)
            expected_state, expected = ref.step(expected_state, inputs, params)
            state, outputs = step(state, inputs, params)
            assert _exact((state, outputs)) == _exact((expected_state, expected)), (strategy, variant, k, inputs)
            assert _exact(plan_cycle(speed, inputs, params)) == _exact(ref.plan_cycle(speed, inputs, params))
            modes.add(outputs.mode)
    if noise == 0.0:  # the clean drives reach the planner's modes, not only FAULT
        assert {Mode.STANDBY, Mode.CONTINGENCY} <= modes
        assert (Mode.TIGHTENING in modes) == (strategy in ("tightening", "adaptive"))
