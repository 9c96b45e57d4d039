"""The design of a sweep: which axis values each run gets.

* ``grid``: the Cartesian product of every axis (the last axis varies fastest).
* ``monte_carlo``: ``samples`` draws of the distribution axes, each crossed with
  every combination of the list/range axes (so strategies are compared on the
  same draws). A draw maps a uniform ``u`` in (0, 1) through the inverse CDF:
  uniform ``low + u (high - low)``; normal ``mean + std Φ⁻¹(u)``; truncated
  normal ``mean + std Φ⁻¹(Φ(α) + u (Φ(β) - Φ(α)))`` with ``α = (low - mean)/std``,
  ``β = (high - mean)/std``; choice: the first value whose cumulative weight
  exceeds ``u``. Plain sampling takes ``u`` from the generator; the Latin
  hypercube (McKay, Beckman & Conover 1979) takes ``u = (π_j(i) + v) / N`` with
  a random permutation ``π_j`` per axis and ``v`` uniform in [0, 1), so every
  1/N stratum of every axis holds exactly one sample.
* ``one_at_a_time``: the base run, then each non-``cross`` axis's values one at a
  time with the others at their base values (a value equal to the base is not
  repeated), everything crossed with the ``cross`` axes.

The generator is ``numpy.random.default_rng(sweep.seed)``: the design is a
function of the sweep file alone.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from statistics import NormalDist
from typing import Any, Mapping

import numpy as np

from .spec import Axis, SweepSpec

_STD_NORMAL = NormalDist()
_U_EPS = 1e-12  # keeps Φ⁻¹ finite at the ends of (0, 1)


@dataclass(frozen=True)
class Point:
    """One run of the design: ``(path, value)`` per varied axis, and the replicate number."""

    values: tuple[tuple[str, Any], ...]
    replicate: int = 0

    def as_dict(self) -> dict[str, Any]:
        return dict(self.values)


def inverse_cdf(axis: Axis, u: float) -> Any:
    """The value of ``axis`` at cumulative probability ``u`` (see the module docstring)."""
    u = min(max(u, _U_EPS), 1.0 - _U_EPS)
    d = axis.distribution
    if d == "uniform":
        return axis.low + u * (axis.high - axis.low)
    if d == "normal":
        return axis.mean + axis.std * _STD_NORMAL.inv_cdf(u)
    if d == "truncated_normal":
        lo = _STD_NORMAL.cdf((axis.low - axis.mean) / axis.std)
        hi = _STD_NORMAL.cdf((axis.high - axis.mean) / axis.std)
        p = min(max(lo + u * (hi - lo), _U_EPS), 1.0 - _U_EPS)
        return min(max(axis.mean + axis.std * _STD_NORMAL.inv_cdf(p), axis.low), axis.high)
    if d == "choice":
        weights = np.asarray(axis.weights or [1.0] * len(axis.values), dtype=float)
        cumulative = np.cumsum(weights) / weights.sum()
        return axis.values[min(int(np.searchsorted(cumulative, u, side="right")), len(axis.values) - 1)]
    raise ValueError(f"unknown distribution {d!r}")


def unit_samples(n: int, dims: int, rng: np.random.Generator, latin_hypercube: bool) -> np.ndarray:
    """``n × dims`` uniforms in [0, 1): plain, or one per stratum per column (Latin hypercube)."""
    if not latin_hypercube:
        return rng.random((n, dims))
    strata = np.stack([rng.permutation(n) for _ in range(dims)], axis=1)
    return (strata + rng.random((n, dims))) / n


def _plain(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value


def _product(axes: list[Axis]) -> list[tuple[tuple[str, Any], ...]]:
    return [tuple(zip((a.path for a in axes), combo)) for combo in itertools.product(*(a.values for a in axes))]


def _monte_carlo(spec: SweepSpec) -> list[tuple[tuple[str, Any], ...]]:
    sampled = [a for a in spec.axes if a.sampled]
    listed = [a for a in spec.axes if not a.sampled]
    u = unit_samples(spec.samples, len(sampled), np.random.default_rng(spec.seed), spec.latin_hypercube)
    draws = [tuple((a.path, _plain(inverse_cdf(a, float(u[i, j])))) for j, a in enumerate(sampled))
             for i in range(spec.samples)]
    return [draw + combo for draw in draws for combo in _product(listed)]


def _one_at_a_time(spec: SweepSpec, base: Mapping[str, Any]) -> list[tuple[tuple[str, Any], ...]]:
    varied = [a for a in spec.axes if not a.cross]
    crossed = _product([a for a in spec.axes if a.cross])
    at_base = tuple((a.path, base[a.path]) for a in varied)
    singles = [at_base]
    for i, axis in enumerate(varied):
        singles += [at_base[:i] + ((axis.path, v),) + at_base[i + 1:] for v in axis.values if v != base[axis.path]]
    return [single + combo for single in singles for combo in crossed]


def design(spec: SweepSpec, base: Mapping[str, Any]) -> list[Point]:
    """Every run of the sweep, in a fixed order (``base``: each axis path's value in the base scenario)."""
    if spec.mode == "grid":
        combos = _product(list(spec.axes))
    elif spec.mode == "monte_carlo":
        combos = _monte_carlo(spec)
    else:
        combos = _one_at_a_time(spec, base)
    order = {a.path: i for i, a in enumerate(spec.axes)}
    return [Point(tuple(sorted(c, key=lambda kv: order[kv[0]])), r)
            for c in combos for r in range(spec.replicates)]
