"""``none`` (Johnson 2019, section III): plans with 0.9 of the peak deceleration and never tightens.

Selective determinism alone: the driver's command passes until its stopping
path would no longer be disjoint, then the contingency brakes at full scale.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..strategy import FixedDeceleration

if TYPE_CHECKING:
    from ..params import CoreParams


class NoStrategy(FixedDeceleration):
    """D = ``none_decel_fraction`` x peak (0.9)."""

    def decel_fraction(self, params: CoreParams) -> float:
        return params.none_decel_fraction


STRATEGY = NoStrategy()
