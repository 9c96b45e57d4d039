"""The pure core of the active-safety ECU: ``step(state, inputs, params) -> (state, outputs)``.

No I/O, no clock, no logging. Submodules, one concern each, composed by
``step`` in this order: ``track_confirmation`` and ``relevance``, ``validity``
and ``plausibility``, ``speed_estimate``, the strategy (``strategies``, one
module each, in a registry; ``decel_estimate`` is ``adaptive``'s estimate of the achievable
deceleration, our extension), ``plan`` (``proximity``, ``intent``,
``stopping_path``, ``relative_stop``), with planar tracks ``planar`` (the stopping region,
``region``, over every track), ``modes`` and ``degraded``, ``steering`` (the steering
contingency's request), and ``output_gate``.
"""

from .params import STRATEGIES, CoreParams
from .plan import Plan, plan_cycle
from .step import step
from .strategies import REGISTRY  # imported here so that a registry that disagrees with the DBC stops the import
from .types import CoreInputs, CoreOutputs, CoreState, FaultFlag, Mode

__all__ = [
    "REGISTRY", "STRATEGIES", "CoreInputs", "CoreOutputs", "CoreParams", "CoreState", "FaultFlag",
    "Mode", "Plan", "plan_cycle", "step",
]
