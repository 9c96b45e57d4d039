"""``conservative`` (Johnson 2019, section III): plans with 0.8 of the peak deceleration, never tightens.

Like ``none`` but with a longer model stopping path, so the contingency is
invoked earlier; the paper shows the reciprocal dance persists.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..strategy import FixedDeceleration

if TYPE_CHECKING:
    from ..params import CoreParams


class Conservative(FixedDeceleration):
    """D = ``conservative_decel_fraction`` x peak (0.8)."""

    def decel_fraction(self, params: CoreParams) -> float:
        return params.conservative_decel_fraction


STRATEGY = Conservative()
