"""Constraint tightening in the joint space of acceleration, curvature and steering rate.

Johnson 2019, section II-D: each followable path has *nominal* dynamic constraints and the stopping
region's *contingency* constraints "that most quickly bring the agent to a stop"; constraint
tightening moves the nominal bounds toward the contingency's "with respect to some notion of
proximity". The paper gives no equation; we extend the 1-D formalisation of
:mod:`ecu.core.strategies.tightening` (``a_hi = (1 - p) a_max + p (-C)``) to every bound ``b``::

    b_lo(p) = (1 - p) b_lo,nom + p b_lo,cont,    b_hi(p) = (1 - p) b_hi,nom + p b_hi,cont

with the proximity ``p`` of :mod:`ecu.core.proximity` measured on the nominal row's clearance
(:func:`ecu.core.region.decision.proximity_of`; in the 1-D case the same number). Bounds:

* acceleration: nominal ``[-peak_decel, a_max]``, contingency ``[-C, -C]`` (full braking);
* curvature: nominal ``+-min(tan(delta_max)/L, A / v^2)`` (steering angle, friction circle at
  speed ``v``), contingency the chosen path's ``[kappa_c, kappa_c]`` (for ``DRIVER_PATH``, the
  lane's: the contingency braking in lane would use);
* steering rate: nominal ``+-delta_dot_max``, contingency the rate that turns the wheel to
  ``delta_c = atan(kappa_c L)`` within one hold time, ``clamp((delta_c - delta) / t_h, +-delta_dot_max)``.

Blending two intervals with ``lo <= hi`` keeps ``lo <= hi``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from .decision import Contingency, RegionDecision
from .params import RegionParams
from .paths import LANE, EgoState


class JointBounds(NamedTuple):
    """Bounds on acceleration (m/s^2), path curvature (1/m) and road-wheel steering rate (rad/s)."""

    accel_lo_mps2: float
    accel_hi_mps2: float
    curvature_lo_1pm: float
    curvature_hi_1pm: float
    steer_rate_lo_radps: float
    steer_rate_hi_radps: float


def nominal_bounds(ego: EgoState, friction_mps2: float, params: RegionParams) -> JointBounds:
    """The car's own limits: braking to the peak, full throttle, steering angle and friction, steering rate."""
    kappa = math.tan(params.steer_angle_max_rad) / params.wheelbase_m
    if ego.speed_mps > 0.0:
        kappa = min(kappa, friction_mps2 / (ego.speed_mps * ego.speed_mps))
    rate = params.steer_rate_max_radps
    return JointBounds(-params.peak_decel_mps2, params.driver_max_accel_mps2, -kappa, kappa, -rate, rate)


def contingency_bounds(ego: EgoState, decision: RegionDecision, params: RegionParams) -> JointBounds:
    """Full braking along the chosen path (the lane's for ``DRIVER_PATH``), the wheel turned toward it."""
    row = LANE if decision.kind is Contingency.DRIVER_PATH else decision.row
    kappa = float(decision.paths.curvature_1pm[row])
    delta_c = math.atan(kappa * params.wheelbase_m)
    limit = params.steer_rate_max_radps
    rate = min(limit, max(-limit, (delta_c - ego.road_wheel_angle_rad) / params.hold_time_s))
    c = -params.contingency_decel_mps2
    return JointBounds(c, c, kappa, kappa, rate, rate)


def tightened_bounds(ego: EgoState, decision: RegionDecision, params: RegionParams) -> JointBounds:
    """Every bound blended by the decision's proximity ``p`` (module docstring)."""
    p = decision.proximity
    nominal = nominal_bounds(ego, decision.paths.friction_mps2, params)
    contingency = contingency_bounds(ego, decision, params)
    return JointBounds(*((1.0 - p) * n + p * c for n, c in zip(nominal, contingency)))
