"""``adaptive`` (our extension): ``tightening`` with D from an estimate of what the road allows.

The paper's strategies plan with a fixed fraction of the dry-road peak
deceleration; on a wetter road every one of them collides. ``adaptive``
tightens like ``tightening`` and plans each cycle with
``D = tightening_decel_fraction * a_hat``, where ``a_hat`` is the online
estimate of the achievable deceleration (:mod:`ecu.core.decel_estimate`: the
dry peak before any evidence, so with no evidence it plans exactly like
``tightening``). The estimate only learns from valid, plausible wheel speeds
of a car whose speed estimate is initialised. Wheelspin under drive torque is
plausible (:mod:`ecu.core.plausibility`), so its traction slip is evidence of
a slippery road; from issue 15 to issue 25 the wheel-spread check took it for
a fault, and ``adaptive`` learnt nothing from a spinning start.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .. import decel_estimate
from .tightening import ConstraintTightening

if TYPE_CHECKING:
    from ..decel_estimate import DecelEstimate
    from ..params import CoreParams
    from ..types import CoreInputs, CoreState


class Adaptive(ConstraintTightening):
    """Constraint tightening with ``D = fraction * a_hat``."""

    def cycle_decel(self, state: CoreState, inputs: CoreInputs, speed_mps: float, wheels_ok: bool,
                    params: CoreParams) -> tuple[DecelEstimate, float]:
        """One update of the estimate from this cycle's evidence (unchanged without valid wheel speeds),
        and D with it. The braking commanded last cycle is ``max(our request, brake pedal x peak)``.
        """
        estimate = state.decel
        if state.speed_initialised and wheels_ok:
            request = max(state.prev_decel_request_mps2, inputs.brake_pedal * params.peak_decel_mps2)
            estimate = decel_estimate.update(estimate, state.speed_mps, speed_mps, inputs.wheel_speeds_mps,
                                             request, params)
        return estimate, self.model_decel_mps2(estimate, params)

    def model_decel_mps2(self, estimate: DecelEstimate, params: CoreParams) -> float:
        return params.model_decel_fraction * decel_estimate.achievable_decel_mps2(estimate, params)


STRATEGY = Adaptive()
