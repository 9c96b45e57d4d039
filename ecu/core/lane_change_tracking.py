"""Holding an evasive lane change on its planned path, closed loop (issue 22, rule 3; :mod:`ecu.core.steering`).

The region plans a lane change (:mod:`ecu.core.region.evasion`) as an S in the road's frame at the latch:
an arc ``+kappa`` for ``l``, an arc ``-kappa`` for ``l``, then straight, ``W`` over (signed, left positive,
the sign of ``kappa``), ``l = arccos(1 - |kappa W| / 2) / |kappa|``. Played open loop (the curvature by
distance, then the heading back) the car missed its plan: the steering lag (0.27 s), the rate-limited overlay
against a driver who steers back toward the old lane, and the braking after the S left a heading and a lateral
error that the heading-only return could not take out (measured: late-stationary-free-100 spun off the road).

**The planned pose** at the distance ``s`` travelled since the latch, lateral offset ``y_p``, heading
``psi_p`` and curvature ``kappa_p``::

    s < l:        kappa_p = kappa,   psi_p = kappa s,          y_p = (1 - cos(kappa s)) / kappa
    l <= s < 2l:  kappa_p = -kappa,  psi_p = kappa (2l - s),   y_p = W - (1 - cos(kappa (2l - s))) / kappa
    s >= 2l:      kappa_p = 0,       psi_p = 0,                y_p = W

**The car's pose** is dead-reckoned from the latch, the ECU's own inputs only (it has no map): the heading
``psi`` the integral of the yaw rate, the lateral offset ``y`` that of ``v sin(psi)``, the distance that of
``v`` (:func:`advanced`; the heading at the middle of the cycle, the midpoint rule).

**The law**: with the errors ``e_y = y - y_p`` and ``e_psi = psi - psi_p``, the kinematic errors along the
path obey ``e_y' = e_psi`` and ``e_psi' = kappa - kappa_p`` (per metre; the path-error model of lateral control,
Rajamani, *Vehicle Dynamics and Control*, 2nd ed., sec. 3.5; Snider 2009, CMU-RI-TR-09-08, sec. 2). The command

    kappa_c = kappa_p - e_y / D^2 - 2 e_psi / D,    D = v T

makes them a critically damped pair, ``e'' + 2 e' / D + e / D^2 = 0``: each error decays as ``(1 + s/D)
exp(-s/D)``, in time with the constant ``T`` (:data:`TRACKING_TIME_S`), with no overshoot to swing the car
into the next lane. The steering's inner loop (the overlay's correction by the measured curvature,
:mod:`ecu.core.steering`) makes the car follow ``kappa_c``. Stanley's law (Hoffmann et al., ACC 2007) is the
same idea at the front axle; this form keeps the feedforward of the plan and the two gains explicit.
"""

from __future__ import annotations

import math

from .types import Evasion

#: the tracking loop's time constant T (s). The plant steers through a first-order lag of 0.27 s
#: (fmu_plant/README.md, steering_time_constant) and its yaw rate answers a step of the wheel in 0.255 s
#: (ISO 7401 response time, same README): about 0.5 s from a command to the yaw it asks for. A loop
#: four times slower than its actuator (our choice, the usual separation of an outer loop from the inner
#: one) keeps its damping with that delay: T = 4 x 0.27 s, rounded to 1.0 s (half its S, ``l / v``, is
#: 0.5-0.8 s in the catalogue, so the plan's feedforward, not the feedback, carries the S).
TRACKING_TIME_S = 1.0
#: the smallest speed (m/s) the tracking distance D = v T is taken at (the region's yaw-rate threshold, 1 m/s)
_MIN_SPEED_MPS = 1.0


def half_length_m(kappa_1pm: float, offset_m: float) -> float:
    """``l``: each half of the S of curvature ``kappa_1pm`` that ends ``offset_m`` over (module docstring); a
    curvature too tight for the offset takes a half turn each way."""
    k = max(abs(kappa_1pm), 1e-12)
    return math.acos(max(-1.0, 1.0 - 0.5 * k * abs(offset_m))) / k


def planned_pose(kappa_1pm: float, offset_m: float, travel_m: float) -> tuple[float, float, float]:
    """``(kappa_p, y_p, psi_p)`` at ``travel_m`` along the S (module docstring)."""
    half = half_length_m(kappa_1pm, offset_m)
    k = math.copysign(max(abs(kappa_1pm), 1e-12), kappa_1pm)
    end = 2.0 * (1.0 - math.cos(k * half)) / k
    if travel_m <= 0.0:
        return k, 0.0, 0.0
    if travel_m < half:
        return k, (1.0 - math.cos(k * travel_m)) / k, k * travel_m
    if travel_m < 2.0 * half:
        left = 2.0 * half - travel_m
        return -k, end - (1.0 - math.cos(k * left)) / k, k * left
    return 0.0, end, 0.0


def tracking_curvature(kappa_1pm: float, evasion: Evasion, speed_mps: float) -> float:
    """``kappa_c``: the curvature that brings the car back onto its planned S (module docstring, The law); an arc's
    own ``kappa_1pm`` when the held path is not a lane change (``offset_m`` 0)."""
    if evasion.offset_m == 0.0:
        return kappa_1pm
    kappa_ff = planned_pose(kappa_1pm, evasion.offset_m, evasion.travel_m)[0]
    _, y_p, psi_p = planned_pose(kappa_1pm, evasion.offset_m, evasion.travel_m - evasion.lead_m)
    d = max(speed_mps, _MIN_SPEED_MPS) * TRACKING_TIME_S
    return kappa_ff - (evasion.lateral_m - y_p) / (d * d) - 2.0 * (evasion.heading_rad - psi_p) / d


def advanced(evasion: Evasion, speed_mps: float, yaw_rate_radps: float, cycle_s: float) -> Evasion:
    """The lane change's dead-reckoned pose one cycle on (module docstring, The car's pose)."""
    if evasion.offset_m == 0.0:
        return evasion
    turn = yaw_rate_radps * cycle_s
    ds = speed_mps * cycle_s
    return Evasion(evasion.offset_m, evasion.lead_m, evasion.travel_m + ds, evasion.heading_rad + turn,
                   evasion.lateral_m + ds * math.sin(evasion.heading_rad + 0.5 * turn))
