"""Conversions between the DBC's units and SI (the codec boundary).

The DBC carries the units a bus carries (km/h, %, ms); crd computes in SI
(m/s, fractions, s): ``si = dbc_value / dbc_per_si(unit)`` and
``dbc_value = si * dbc_per_si(unit)``. (Dividing by 3.6 rather than
multiplying by 1/3.6 keeps the results bit-identical to the arithmetic the
codec boundary has always done.)
"""

from __future__ import annotations

import math

#: km/h in one m/s (1 m/s = 3600 m / 1000 h)
KMH_PER_MPS = 3.6
#: per cent in one unit fraction
PERCENT = 100.0
#: DBC unit -> DBC units per SI unit; "" marks a dimensionless signal (counts, flags, enumerations)
DBC_PER_SI: dict[str, float] = {
    "": 1.0,
    "m": 1.0,
    "m/s": 1.0,
    "m/s^2": 1.0,
    "km/h": KMH_PER_MPS,
    "%": PERCENT,
    "ms": 1000.0,
    "deg": 180.0 / math.pi,
    "deg/s": 180.0 / math.pi,
}


def dbc_per_si(unit: str) -> float:
    """DBC units per SI unit for ``unit``; raises ``KeyError`` for a unit the table lacks."""
    try:
        return DBC_PER_SI[unit]
    except KeyError:
        raise KeyError(f"DBC unit {unit!r}: expected one of {sorted(DBC_PER_SI)}") from None
