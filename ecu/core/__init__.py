"""The pure core of the active-safety ECU: ``step(state, inputs, params) -> (state, outputs)``.

No I/O, no clock, no logging. Submodules, one concern each: ``speed_estimate``,
``stopping_path``, ``strategies`` (driver intent, proximity, tightening),
``validity``, ``modes``, ``output_gate``, ``decel_estimate`` (the ``adaptive``
strategy's estimate of the achievable deceleration, our extension); ``step``
ties them together.
"""

from .params import STRATEGIES, CoreParams
from .step import Plan, plan_cycle, step
from .types import CoreInputs, CoreOutputs, CoreState, FaultFlag, Mode

__all__ = [
    "STRATEGIES", "CoreInputs", "CoreOutputs", "CoreParams", "CoreState", "FaultFlag",
    "Mode", "Plan", "plan_cycle", "step",
]
