"""Relevance: is the radar's object in our path?

The radar's ``ObjectLateral`` is the object's centre offset from our path
(m, left positive). The ECU does not know the object's width, so the path
is widened by a margin that covers the widest body it must protect against::

    in_path  <=>  |lateral| <= vehicle_width_m / 2 + path_margin_m

With our width 1.815 m (Euro NCAP's reference VUT) and ``path_margin_m`` =
1.0 m (half the ISO 19206-3 car target's 1.712 m width, plus 0.144 m for
lateral error) the corridor is ±1.91 m: every car target that overlaps our
body is in it; a car in the adjacent lane (3.5 m), a cyclist passed with
1.5 m clearance (2.66 m) or a lead car that has cut out are not. An object
outside the path triggers nothing: the planner treats it as no object.
"""

from __future__ import annotations

from .params import CoreParams


def in_path(lateral_m: float, params: CoreParams) -> bool:
    """True when an object centred ``lateral_m`` (m) off our path is in it (NaN: in it, fail-safe)."""
    return not abs(lateral_m) > params.vehicle_width_m / 2.0 + params.path_margin_m
