"""What a collision-avoidance strategy decides each cycle: the :class:`Strategy` Protocol.

A strategy (Johnson 2019, section III; ``adaptive`` is our extension) decides

* the model deceleration D its stopping paths plan with: a fraction of the
  peak deceleration (``decel_fraction``), or an estimate of what the road
  allows that it keeps and updates (``cycle_decel``; ``model_decel_mps2`` is
  D for a given estimate);
* whether and how it tightens the driver's acceleration bound as the stopping
  path nears the contingency boundary (``tighten``; :data:`NO_TIGHTENING`
  leaves the driver's command alone).

The strategies themselves are the modules of :mod:`ecu.core.strategies`, one
each, in its registry. :class:`FixedDeceleration` is the common base of those
without an estimate.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple, Protocol, runtime_checkable

if TYPE_CHECKING:
    from .decel_estimate import DecelEstimate
    from .params import CoreParams
    from .types import CoreInputs, CoreState

FULL_THROTTLE_PCT = 100.0


class Tightening(NamedTuple):
    """The tightened upper bound on the driver's acceleration and how it reaches the car (immutable)."""

    proximity: float
    accel_upper_mps2: float
    throttle_limit_pct: float
    decel_request_mps2: float
    #: the bound takes something from the driver: ``throttle_limit_pct < 100 or decel_request_mps2 > 0``
    restricts: bool


#: no bound: the driver's command passes (min(a_drv, inf) is a_drv for every float, NaN too)
NO_TIGHTENING = Tightening(0.0, float("inf"), FULL_THROTTLE_PCT, 0.0, False)


@runtime_checkable
class Strategy(Protocol):
    """What a collision-avoidance strategy decides each cycle."""

    def decel_fraction(self, params: CoreParams) -> float:
        """f in ``D = f * peak_decel_mps2``, the fixed model deceleration (the prior of an estimate)."""

    def cycle_decel(self, state: CoreState, inputs: CoreInputs, speed_mps: float, wheels_ok: bool,
                    params: CoreParams) -> tuple[DecelEstimate, float]:
        """(the achievable-deceleration estimate after this cycle, D for this cycle); a strategy without
        an estimate: ``(state.decel, params.model_decel_mps2)``.

        ``speed_mps``: this cycle's speed estimate; ``wheels_ok``: the wheel speeds are valid and plausible.
        """

    def model_decel_mps2(self, estimate: DecelEstimate, params: CoreParams) -> float:
        """D (m/s^2) with ``estimate``; ``params.model_decel_mps2`` for a strategy without one."""

    def tighten(self, proximity: float, params: CoreParams) -> Tightening:
        """The bound on the driver's acceleration at ``proximity``; :data:`NO_TIGHTENING` for none."""


class FixedDeceleration:
    """A strategy that plans with ``D = decel_fraction * peak_decel_mps2`` every cycle and does not tighten.

    Subclasses give :meth:`decel_fraction`; one that tightens overrides :meth:`tighten`.
    """

    def decel_fraction(self, params: CoreParams) -> float:
        raise NotImplementedError(f"{type(self).__name__}: a strategy names its deceleration fraction")

    def cycle_decel(self, state: CoreState, inputs: CoreInputs, speed_mps: float, wheels_ok: bool,
                    params: CoreParams) -> tuple[DecelEstimate, float]:
        return state.decel, params.model_decel_mps2

    def model_decel_mps2(self, estimate: DecelEstimate, params: CoreParams) -> float:
        return params.model_decel_mps2

    def tighten(self, proximity: float, params: CoreParams) -> Tightening:
        return NO_TIGHTENING
