"""Parameters of the stopping region: the ego's geometry and steering limits, the path family's
resolution, the emergency-steering limits, and the assumed capability of each object class.

Every number has its source here; the quantities the 1-D core already declares (hold time,
model and contingency deceleration, standoff, full-throttle acceleration, proximity margin) are
read from :class:`ecu.core.params.CoreParams` by :func:`region_params`, so one parameter set
serves both.

Ego geometry (the builtin planar plant, ``fmu_plant/README.md`` and
``cosim/scenarios/config.py``): body 4.358 x 1.815 m (Euro NCAP's reference VUT), wheelbase
2.7 m, centre of gravity 1.2 m behind the front axle, the box centred on the centre of gravity;
so the rear axle, the reference point of the kinematic paths, is ``1.5 + 4.358 / 2 = 3.679 m``
behind the front bumper. Steering (CommonRoad vehicle 2, BMW 320i; planar-protocol-facts.md
S9 table 5.1): road-wheel angle within +-1.066 rad, rate within +-0.4 rad/s (the DBC's
``SigMaxRate`` of ``SteerAngleRequest``, 23 deg/s); the plant's steering lag 0.27 s
(``steering_time_constant``, Autoware's identified by-wire actuator).

Emergency steering (UN R79 Rev. 4, planar-protocol-facts.md section 4): R79 gives **no numeric
lateral-acceleration cap for ESF or CSF** (unconfirmed against the UNECE text); we apply the
ACSF B1 upper bound for M1/N1, 3 m/s^2 (S5 table 1), to every path the ECU steers, and the
lateral-jerk target 0.5 g/s ~ 5 m/s^3 (S7; "<= 5 m/s^3" wording unconfirmed) to its curvature
rate. ESF "must not lead the vehicle off the road ... nor into another road user" (S5): the road
and occupied-lane test of :mod:`ecu.core.region.decision`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Mapping, NamedTuple

import numpy as np

from can_dbc.contract import enumeration

from ..params import CoreParams

GRAVITY_MPS2 = 9.81


class ClassCapability(NamedTuple):
    """An object class's box and the motion it is assumed capable of while it stops.

    The stopping region of a moving object of speed ``v`` (:mod:`ecu.core.region.objects`): its box
    swept along its velocity over ``s = (v + a rho / 2) rho + v_rho^2 / (2 decel_mps2)``, ``v_rho = v + a rho``
    (it goes on for its response time ``rho`` = ``response_s``, speeding up at ``a`` = ``accel_mps2``, then
    brakes: RSS's stopping distance of a road user, S16), and widened on each side by
    ``y = min(lateral_reach_max_m, lateral_accel_mps2 t^2 / 2)``, ``t = rho + v_rho / decel_mps2``.
    ``decel_mps2`` is the *weakest* braking it is assumed to use: the region (a union over time)
    then contains the space of every harder stop.
    """

    length_m: float
    width_m: float
    decel_mps2: float
    lateral_accel_mps2: float
    lateral_reach_max_m: float
    #: before it brakes, it may go on for this long, speeding up at ``accel_mps2`` (RSS's response time)
    response_s: float = 0.0
    accel_mps2: float = 0.0


# Boxes: the DBC's comment of Track<i>SizeClass (Euro NCAP targets as Vector's OSC-NCAP-scenarios encodes
# them: EPTa 0.6 x 0.5, EBTa 1.89 x 0.5, GVT 4.0 x 1.7 m); motorcycle 2.08 x 0.79 m (S4, planar-protocol-facts
# 1.1); truck 12 x 2.55 m (EU Directive 96/53/EC maximum rigid-vehicle length and width; from memory, not in
# planar-protocol-facts.md).
# Capabilities: cars, motorcycles: RSS alpha_brake,min 4 m/s^2 and lateral alpha_lat,accel,max 0.2 m/s^2
# (ad-rss-lib defaults, S16), the lateral reach capped at RSS's 0.5 m lane margin (3 m lane, 2 m car, S16);
# trucks: RSS alpha_brake,min,correct 3 m/s^2 (a heavy vehicle brakes less); pedestrians: CARLA's pedestrian
# brake_min 2 m/s^2 and accel_max 2 m/s^2 taken in any direction, and its response_time 0.5 s (S17), reach capped
# at 1 m (one stride); bicycles: the truck's 3 m/s^2 (a cyclist braking without lifting the rear wheel) and the
# car's lateral limits, argued, no cited figure, and RSS's response time of other road users, 2 s (ad-rss-lib's
# rho_other, CARLA's for other vehicles, S16, S17) at the speed it has (no speeding up: argued; CARLA's 3.5 m/s^2
# is a car's). UNKNOWN takes the weakest braking, the widest reach and the longest response of all, with a
# car's box. Response times (issue 22, round 32): with none, a pedestrian or cyclist was assumed to brake the
# moment it was seen, so the contingency waited until our stopping path touched a region ~1 m ahead of a walker,
# and one who walked on was hit (ncap_vru, tightening: 16 cells the oracle avoids); with them 4 remain, 3 of them
# out of the radar's sight. Motor vehicles keep none (each of them here is an equipped car or a test target; with
# RSS's 2 s a car at 50 km/h would claim 28 m more of the road ahead of it: not tried, a known asymmetry).
_BY_NAME = {
    "UNKNOWN": ClassCapability(4.0, 1.7, 2.0, 2.0, 1.0, 2.0, 2.0),
    "PEDESTRIAN": ClassCapability(0.6, 0.5, 2.0, 2.0, 1.0, 0.5, 2.0),
    "BICYCLE": ClassCapability(1.89, 0.5, 3.0, 0.2, 0.5, 2.0, 0.0),
    "MOTORCYCLE": ClassCapability(2.08, 0.79, 4.0, 0.2, 0.5),
    "CAR": ClassCapability(4.0, 1.7, 4.0, 0.2, 0.5),
    "TRUCK": ClassCapability(12.0, 2.55, 3.0, 0.2, 0.5),
}
#: DBC value of ``Track<i>SizeClass`` -> its capability (the DBC's VAL_ table names the classes)
CAPABILITIES: Mapping[int, ClassCapability] = MappingProxyType(
    {value: _BY_NAME[name] for value, name in enumeration("RadarTrack0", "Track0SizeClass").items()})


@dataclass(frozen=True, slots=True)
class RegionParams:
    """Everything the stopping region's arithmetic depends on (SI units; sources in the module docstring)."""

    length_m: float = 4.358
    width_m: float = 1.815
    rear_axle_to_front_m: float = 3.679
    wheelbase_m: float = 2.7
    steer_angle_max_rad: float = 1.066
    steer_rate_max_radps: float = 0.4
    steer_lag_s: float = 0.27
    emergency_lat_accel_max_mps2: float = 3.0
    emergency_lat_jerk_max_mps3: float = math.inf
    #: steering paths: lateral-acceleration levels evenly spaced over +-emergency_lat_accel_max_mps2 (odd:
    #: 13 levels are 0.5 m/s^2 apart, ISO 4138's step for steady-state circles, S12)
    steer_paths: int = 13
    #: boxes per stopping path; each covers the motion since the previous one (module paths)
    path_samples: int = 8
    #: tracks are inflated by this many standard deviations of their position
    sigma_factor: float = 3.0
    #: ego box widened on each side by the RSS lateral fluctuation margin delta_lat,min (S16)
    lateral_margin_m: float = 0.1
    #: below this speed the path's curvature comes from the wheel angle, above it from the yaw rate
    yaw_rate_min_speed_mps: float = 1.0
    # from CoreParams (region_params): hold time t_h, standoff, full throttle, contingency braking, margins
    hold_time_s: float = 0.11
    standoff_m: float = 2.0
    driver_max_accel_mps2: float = 3.0
    peak_decel_mps2: float = 9.0
    contingency_decel_mps2: float = 15.0
    proximity_margin_m: float = 10.0
    moving_object_speed_mps: float = 0.5
    #: how far a track's velocity over ground may be off: its heading's uncertainty when its box is placed (module
    #: objects). 0, not CoreParams.track_speed_tolerance_mps (0.5): with it, and with the cyclists' response time,
    #: a cyclist passed at 1.5 m reached our path (planar_false_positive pass-cyclist-1.5m: 4 interventions, round
    #: 32); without it a car crossing just ahead whose heading reads 5 degrees off is not wholly covered
    #: (tests/ecu/region/test_objects.py): a known gap, left until the track's velocity is corrected for the
    #: radar's latency
    velocity_tolerance_mps: float = 0.0

    #: derived once: the steering rows' lateral accelerations, and the samples' fractions k / M of s_stop
    lateral_levels_mps2: np.ndarray = field(init=False, repr=False, compare=False)
    sample_fractions: np.ndarray = field(init=False, repr=False, compare=False)
    #: the standoff ahead of each sample's box: only the last, where the car stops
    standoff_at_samples_m: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if self.steer_paths < 1 or self.steer_paths % 2 == 0:
            raise ValueError(f"RegionParams.steer_paths: expected an odd count >= 1, got {self.steer_paths}")
        if self.path_samples < 1:
            raise ValueError(f"RegionParams.path_samples: expected >= 1, got {self.path_samples}")
        a = self.emergency_lat_accel_max_mps2
        object.__setattr__(self, "lateral_levels_mps2", np.linspace(-a, a, self.steer_paths))
        object.__setattr__(self, "sample_fractions", np.arange(1, self.path_samples + 1) / self.path_samples)
        standoff = np.zeros(self.path_samples)
        standoff[-1] = self.standoff_m
        object.__setattr__(self, "standoff_at_samples_m", standoff)


def region_params(core: CoreParams, **overrides: float) -> RegionParams:
    """The region's parameters with the 1-D core's shared quantities taken from ``core``."""
    shared = {"hold_time_s": core.hold_time_s, "standoff_m": core.standoff_m,
              "driver_max_accel_mps2": core.driver_max_accel_mps2, "peak_decel_mps2": core.peak_decel_mps2,
              "contingency_decel_mps2": core.contingency_decel_mps2,
              "proximity_margin_m": core.proximity_margin_m, "width_m": core.vehicle_width_m,
              "moving_object_speed_mps": core.moving_object_speed_mps}
    return RegionParams(**{**shared, **overrides})
