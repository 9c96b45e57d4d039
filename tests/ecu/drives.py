"""Seeded random drives of the ECU core, and their record of every state, output and plan, exactly.

A drive (one strategy, one input-noise rate, the four parameter variants of
:data:`VARIANTS`, 600 cycles each) approaches, brakes behind, follows and meets
objects, some beside the path, with inputs that are, at the noise rate, timed
out, stamped in the future, E2E-invalid, flagged by the receiver, implausible
or not finite. :func:`record_drive` runs one through a core and returns every
cycle's state, outputs and :func:`ecu.core.plan_cycle` as a digest of their
exact text (every float by ``repr``, every value with its type), and the
outputs' decisions in full. ``test_step_golden.py`` compares them with those
recorded from the core (``data/step_golden.npz``; see that test for its history).
The planar fields added by issue 22 (:data:`PLANAR_DEFAULTS`) are not in the
digest: these drives carry no planar tracks, so every cycle must hold their
values of a run without them, which :func:`recorded` asserts.
"""

from __future__ import annotations

import hashlib
from collections import namedtuple
import math
import random
from typing import Callable, Iterator

import numpy as np

from ecu.core import CoreInputs, CoreParams, CoreState

ODD = (math.nan, math.inf, -math.inf, -1.0, 0.0, 1e300, 2.0)
VARIANTS = ({}, {"driven_axle": "rear"}, {"driven_axle": "all"},
            {"contingency_release_ratio": 1.3, "contingency_release_speed_mps": 0.5})
STRATEGIES = ("none", "conservative", "tightening", "adaptive")
NOISES = (0.0, 0.0005, 0.003, 0.02)
CYCLES = 600
#: the outputs kept in full beside the digests, to show what a differing cycle decided
DECISIONS = ("mode", "override_active", "throttle_limit_pct", "brake_decel_request_mps2", "fault_flags",
             "disjoint", "gate_intervened")


def random_inputs(rng: random.Random, t_s: float, speed_mps: float, range_m: float, rate_mps: float,
                  noise: float) -> CoreInputs:
    """One cycle's inputs around the true motion, each odd at the rate ``noise``."""
    def odd(good, bad):
        return rng.choice(bad) if rng.random() < noise else good

    wheels = tuple(odd(max(0.0, speed_mps + rng.gauss(0.0, 0.1)), ODD) for _ in range(4))
    if rng.random() < 5 * noise:  # locked or spinning wheels
        wheels = tuple(speed_mps * rng.uniform(0.3, 1.5) for _ in range(4))
    elif rng.random() < 0.02:  # a spread at the slip bound (2 m/s + 30 % of the fastest wheel, the defaults),
        top = speed_mps + 1.0 + 0.1 * speed_mps  # the mean rising: not braking, so the bound is checked
        wheels = (top, top, max(0.0, 0.7 * top - 2.0 + rng.choice((-0.005, 0.0, 0.005))), top)
    brake = rng.choice((0.0,) * 30 + (1.0, rng.random(), 0.6))
    accel = rng.choice((0.0, 1.0, 1.0, 1.0, 0.3, rng.random())) if brake <= 0.5 else odd(0.0, (0.6, 1.0))
    rx = (lambda: t_s - odd(0.0, (0.01, 0.04, 0.06, 0.3, 1.0, -0.01, math.inf)))
    # drawn in this order (the seeded stream must not change), then named
    accel_pedal = odd(accel, (0.6, -0.1, 1.1, math.nan))
    object_valid = rng.random() < 0.9
    object_range_m = odd(max(0.0, range_m + rng.gauss(0.0, 0.2)), ODD)
    object_range_rate_mps = odd(rate_mps + rng.gauss(0.0, 0.2), ODD)
    wheel_rx_t_s, driver_rx_t_s, object_rx_t_s = rx(), rx(), rx()
    scores = odd(0, (1, 4, 5, 6)), odd(0, (5,)), odd(0, (5,))
    lateral_m = rng.choice((0.0,) * 10 + (0.5, 1.9, 2.0, 3.5, -1.0, odd(0.0, (math.nan,))))
    return CoreInputs(
        t_s=t_s, wheel_speeds_mps=wheels, accel_pedal=accel_pedal, brake_pedal=brake, object_valid=object_valid,
        object_range_m=object_range_m, object_range_rate_mps=object_range_rate_mps,
        wheel_rx_t_s=wheel_rx_t_s, driver_rx_t_s=driver_rx_t_s, object_rx_t_s=object_rx_t_s,
        wheel_e2e_score=scores[0], driver_e2e_score=scores[1], object_e2e_score=scores[2],
        object_lateral_m=lateral_m, wheel_rx_flags=odd(0, (32, 4096)), driver_rx_flags=odd(0, (32,)),
        object_rx_flags=odd(0, (32, 4096)), node_flags=odd(0, (512, 1024, 2048)))


def drive(strategy: str, noise: float) -> Iterator[tuple[CoreParams, int, float, CoreInputs]]:
    """(params, cycle k, true speed, inputs) of the seeded drive; the state restarts with each variant."""
    rng = random.Random(f"{strategy}/{noise}")
    for variant in VARIANTS:
        params = CoreParams(strategy=strategy, **variant)
        speed, range_m, object_mps = rng.uniform(0, 30), rng.uniform(0, 80), rng.choice((0.0, 5.0, -5.0, 20.0))
        for k in range(CYCLES):
            speed = max(0.0, speed + rng.choice((3.0, -9.0, 0.0, -3.0)) * 0.03 * rng.random())
            range_m -= (speed - object_mps) * 0.01
            if range_m < 0.0 or rng.random() < 0.005:
                range_m, speed = rng.uniform(0, 80), rng.uniform(0, 30)
            yield params, k, speed, random_inputs(rng, k * 0.01, speed, range_m, object_mps - speed, noise)


def exact(value: object) -> str:
    """A canonical text of ``value``, equal only for equal values of equal types, bit for bit: floats by
    ``repr`` (NaN equals NaN, -0.0 differs from 0.0), every value with its type's name, records nested."""
    if isinstance(value, tuple):
        return f"{type(value).__name__}({','.join(exact(v) for v in value)})"
    return f"{type(value).__name__}:{value!r}"


#: the planar fields (issue 22) and their values without planar tracks or steering authority: these drives have
#: neither, so every cycle must hold them; the digest covers the fields recorded before them
PLANAR_DEFAULTS = {"steer_curvature_1pm": "None", "steer_request_rad": "0.0", "steer_active": "False",
                   "region": "None"}


def recorded(record: tuple) -> tuple:
    """``record`` without its planar fields, after checking that each holds its value of a run without them."""
    fields = record._fields
    for name, default in PLANAR_DEFAULTS.items():
        if name in fields:
            value = getattr(record, name)
            assert repr(value) == default, f"{type(record).__name__}.{name} = {value!r} in a drive without tracks"
    legacy = _LEGACY.get(type(record))
    if legacy is None:  # a record type of the same name with the fields recorded before issue 22
        legacy = _LEGACY[type(record)] = namedtuple(type(record).__name__,
                                                    [name for name in fields if name not in PLANAR_DEFAULTS])
    return legacy._make(v for name, v in zip(fields, record) if name not in PLANAR_DEFAULTS)


_LEGACY: dict[type, type] = {}


def record_drive(strategy: str, noise: float, step: Callable, plan_cycle: Callable) -> tuple[np.ndarray, np.ndarray]:
    """Every cycle's (state, outputs, plan_cycle(true speed, inputs)): (8-byte BLAKE2b digests of their
    :func:`exact` text, uint64 [cycles]; the :data:`DECISIONS` fields of the outputs, float64 [cycles, 7])."""
    digests, decisions = [], []
    state = CoreState()
    for params, k, speed, inputs in drive(strategy, noise):
        if k == 0:
            state = CoreState()
        state, outputs = step(state, inputs, params)
        text = exact((recorded(state), recorded(outputs), plan_cycle(speed, inputs, params)))
        digests.append(int.from_bytes(hashlib.blake2b(text.encode(), digest_size=8).digest(), "little"))
        decisions.append([float(getattr(outputs, name)) for name in DECISIONS])
    return np.array(digests, dtype=np.uint64), np.array(decisions, dtype=np.float64)


def key(strategy: str, noise: float) -> str:
    """The drive's name in the golden file."""
    return f"{strategy}/{noise}"
