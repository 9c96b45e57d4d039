"""Behind a moving object: stop at zero RELATIVE speed, and release as the gap opens.

For a moving object (:func:`ecu.core.stopping_path.closing_speed_mps`) the
paper's "stop" is zero relative speed (Johnson 2019, footnote 1). With the
relative speed ``u = -range_rate`` (positive closing, NEGATIVE when the gap
opens), the command ``a`` held for ``t_h`` and then braking at ``D`` against
an object at constant speed, the relative displacement toward the object is::

    x(t) = u t + a t^2 / 2            (0 <= t <= t_h)
    u_h  = u + a t_h
    approach = max over the path of x = x(t_h) + u_h^2 / (2D)   if u_h > 0
             = u^2 / (-2a)                                        if u > 0 >= u_h
             = 0                                                   otherwise

The path is disjoint when ``approach + standoff <= range`` OR when
``approach == 0``: a path that never brings us closer cannot be made safer by
braking. So after braking to zero relative speed the contingency releases as
soon as the gap opens under the driver's command, instead of braking on to a
standstill while the range is below the standoff.

**The object's own stopping region** (issue 22, "braking targets"): the constant-speed
assumption above misses a lead that brakes. The lead's stopping region along our path ends
where it stops if it brakes as hard as a car can on a dry road, ``peak_decel_mps2`` (the
weakest end of its region, so every weaker braking ends further on)::

    s_lead = v_obj^2 / (2 peak_decel)        v_obj = v_ego + r_dot

and our command's stopping path to standstill (:func:`ecu.core.stopping_path.stopping_distance_m`,
at the model D) must stay clear of it: ``d + standoff <= r + s_lead``. While the gap closes
(``r_dot < 0``) both checks must hold; while it opens, the first alone (as above: braking cannot
make an opening gap safer, so a contingency is not held on behind a faster car). The second applies
to an object faster than ``lead_region_speed_mps`` (6 m/s). A standing object never reads that fast:
the radar's latency against this cycle's speed estimate (up to 0.3 s x 5 m/s^2 in the studies of
docs/investigations.md) and a tracker's lag make it read a few m/s at most, so a standing object's
results stay those of the standing checks (the paper run, every standing-target cell of the 1-D
catalogues, the bundled sweeps and the dance study: unchanged). The price: a lead that has braked
below 6 m/s is judged at constant speed again, and ``none`` and ``conservative``, which do not
tighten, still hit the bundled ``braking_lead`` (12 m behind a lead braking at 6 m/s^2). A latch on
the track (seen faster than that, judged by its region until the track ends) is the next step.
Following at equal speeds the second asks for ``r >= v t_h + standoff + v^2 (1/(2D) - 1/(2 peak))``
(14 m at 130 km/h with D = 0.9 peak: less than Euro NCAP's 1 s headway of CCRb), so it binds only
when the lead brakes, or when we close on a slower object faster than the first check allows for.

Tightening's proximity margin for a moving object is a time at the closing
speed (``proximity_time_s``), capped at ``proximity_margin_m`` and floored at
``proximity_margin_min_m``: following at a steady gap (closing ~0) is normal
driving and is not "near the contingency boundary" (Euro NCAP starts its
tests at TTC 4 s; a range-only margin engaged at ~12 m whatever the closing
speed). Stationary objects keep the range margin of the paper reproduction.
"""

from __future__ import annotations

from .params import CoreParams
from .stopping_path import stopping_distance_m


def relative_approach_m(range_rate_mps: float, accel_mps2: float, params: CoreParams,
                        decel_mps2: float | None = None) -> float:
    """How much closer (m, >= 0) the command's stopping path brings us to a constant-speed object.

    ``decel_mps2`` overrides D (the ``adaptive`` strategy's estimate).
    """
    u, a, t_h = -range_rate_mps, accel_mps2, params.hold_time_s
    d = params.model_decel_mps2 if decel_mps2 is None else decel_mps2
    u_h = u + a * t_h
    if u_h > 0.0:
        return max(0.0, u * t_h + 0.5 * a * t_h * t_h + u_h * u_h / (2.0 * d))
    if u > 0.0:
        return u * u / (-2.0 * a)
    return 0.0


def relative_disjoint(approach_m: float, range_m: float, params: CoreParams) -> bool:
    """Disjoint behind a moving object: never closer, or ``approach + standoff <= range``."""
    return approach_m <= 0.0 or approach_m + params.standoff_m <= range_m


def moving_margin_m(closing_mps: float, params: CoreParams) -> float:
    """Tightening's proximity margin (m) for a moving object at ``closing_mps``."""
    scaled = closing_mps * params.proximity_time_s
    return min(params.proximity_margin_m, max(params.proximity_margin_min_m, scaled))


def is_moving(speed_mps: float, range_rate_mps: float, params: CoreParams) -> bool:
    """The object's own speed ``v + range_rate`` exceeds ``moving_object_speed_mps`` (as in stopping_path)."""
    return speed_mps + range_rate_mps > params.moving_object_speed_mps


def moving_proximity(range_m: float, range_rate_mps: float, params: CoreParams,
                     decel_mps2: float | None = None, speed_mps: float | None = None) -> float:
    """Tightening's proximity for a moving object: 0 when even full throttle would not close the gap.

    ``m = range - standoff - approach(full throttle)``, ``p = clamp(1 - m / moving_margin_m, 0, 1)``; with
    ``speed_mps`` given and the gap closing, ``m`` is also at most the full-throttle margin to the end of the
    object's stopping region (:func:`clear_of_lead_m`), so that tightening sees the boundary the
    contingency keeps.
    """
    approach = relative_approach_m(range_rate_mps, params.driver_max_accel_mps2, params, decel_mps2)
    if approach <= 0.0:
        return 0.0
    margin = range_m - params.standoff_m - approach
    if speed_mps is not None and lead_region_applies(speed_mps, range_rate_mps, params):
        d = params.model_decel_mps2 if decel_mps2 is None else decel_mps2
        margin = min(margin, clear_of_lead_m(speed_mps, params.driver_max_accel_mps2, range_m, range_rate_mps,
                                             params, d))
    p = 1.0 - margin / moving_margin_m(max(0.0, -range_rate_mps), params)
    return min(1.0, max(0.0, p))


def lead_stop_m(speed_mps: float, range_rate_mps: float, params: CoreParams) -> float:
    """How far ahead of its present position (m) the object stops braking at ``peak_decel_mps2``."""
    v_obj = max(0.0, speed_mps + range_rate_mps)
    return v_obj * v_obj / (2.0 * params.peak_decel_mps2)


def clear_of_lead_m(speed_mps: float, accel_mps2: float, range_m: float, range_rate_mps: float,
                    params: CoreParams, decel_mps2: float) -> float:
    """``r + s_lead - d - standoff`` (m): how far our command's stopping path to standstill ends short of
    the end of the object's stopping region (negative: they overlap)."""
    stop_m = stopping_distance_m(speed_mps, accel_mps2, params.hold_time_s, decel_mps2)
    return range_m + lead_stop_m(speed_mps, range_rate_mps, params) - stop_m - params.standoff_m


def lead_region_applies(speed_mps: float, range_rate_mps: float, params: CoreParams) -> bool:
    """The object's own stopping region is checked: the gap closes and the object moves faster than
    ``lead_region_speed_mps`` (module docstring)."""
    return range_rate_mps < 0.0 and speed_mps + range_rate_mps > params.lead_region_speed_mps
