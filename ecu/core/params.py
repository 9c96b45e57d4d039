"""Parameters of the pure ECU core: one frozen dataclass, every number a field.

Units are SI and named in the field. ``strategy`` names one of the registry
:data:`ecu.core.strategies.REGISTRY` (the DBC's ``EcuStatus.Strategy``
values: the paper's ``none``, ``conservative`` and ``tightening``, Johnson
2019 section III, and our ``adaptive``). The derived fields are computed once
at construction so the cycle does no table lookups: ``strategy_rules`` (the strategy's
module), ``strategy_code`` (its DBC value), ``hold_time_s`` and, with the
strategy's ``strategy_rules.decel_fraction(params)``,

    model_decel_mps2 = fraction(strategy) * peak_decel_mps2

Every field declares its key once (:func:`ecu.settings.setting`: unit, range
or choices, default, doc); :mod:`ecu.config` checks them (:mod:`ecu.settings`,
the one loader) and the core trusts its parameters. Defaults that are facts of the CAN contract (the cycle, the
reception timeouts, the full-scale deceleration request) are read from the
DBC through :mod:`can_dbc.contract`; the loader refuses values that contradict it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from can_dbc.contract import BRAKE_DECEL_MAX_MPS2, ECU_CYCLE_S, STRATEGY_CODES, timeout_s
from can_dbc.contract import STRATEGIES as DBC_STRATEGIES

from ..settings import Range, setting

from .strategy import Strategy

#: strategy name -> the DBC enumeration value of ``EcuStatus.Strategy`` (its ``VAL_``, lower case);
#: each has its module in :mod:`ecu.core.strategies`.
STRATEGIES = STRATEGY_CODES
#: driven axle name -> wheel indices (FL, FR, RL, RR order) of the *non-driven* wheels.
NON_DRIVEN_WHEELS: dict[str, tuple[int, ...]] = {
    "front": (2, 3),
    "rear": (0, 1),
    "all": (0, 1, 2, 3),
}
#: driven axle name -> indices of the driven wheels when another axle is free to give the reference.
DRIVEN_WHEELS: dict[str, tuple[int, ...]] = {
    name: (() if len(free) == 4 else tuple(i for i in range(4) if i not in free))
    for name, free in NON_DRIVEN_WHEELS.items()
}


@dataclass(frozen=True, slots=True)
class CoreParams:
    """Everything the core's arithmetic depends on (defaults are the lead's starting values)."""

    strategy: str = setting("tightening", allowed=DBC_STRATEGIES,
                            doc="the strategy; the DBC's VAL_ of EcuStatus.Strategy lists them")
    cycle_s: float = setting(ECU_CYCLE_S, unit="s", allowed=Range(0.0, 1.0, low_open=True),
                             doc="ECU cycle; must be the DBC's cycle of SafetyOverride")
    actuation_latency_s: float = setting(0.1, unit="s", allowed=Range(0.0, 5.0),
                                         doc="declared delay from our frame to the brake/powertrain acting on it")
    peak_decel_mps2: float = setting(9.0, unit="m/s^2", allowed=Range(0.0, BRAKE_DECEL_MAX_MPS2, low_open=True),
                                     doc="peak achievable deceleration of the vehicle on dry road")
    none_decel_fraction: float = setting(0.9, allowed=Range(0.0, 1.0, low_open=True),
                                         doc="`none`: model deceleration as a fraction of peak_decel_mps2")
    conservative_decel_fraction: float = setting(0.8, allowed=Range(0.0, 1.0, low_open=True),
                                                 doc="`conservative`: model deceleration fraction")
    tightening_decel_fraction: float = setting(0.9, allowed=Range(0.0, 1.0, low_open=True),
                                               doc="`tightening` and `adaptive`: model deceleration fraction")
    standoff_m: float = setting(2.0, unit="m", allowed=Range(0.0, 100.0),
                                doc="the stopping path must end at least this far before the object")
    driver_max_accel_mps2: float = setting(3.0, unit="m/s^2", allowed=Range(0.0, 20.0, low_open=True),
                                           doc="acceleration attributed to a fully pressed accelerator pedal")
    proximity_margin_m: float = setting(
        10.0, unit="m", allowed=Range(0.0, 250.0, low_open=True),
        doc="constraint tightening: proximity grows from 0 to 1 as the nominal stopping path's margin "
            "to the standoff shrinks from this distance to zero")
    contingency_release_ratio: float = setting(
        1.0, allowed=Range(1.0, 10.0),
        doc="a contingency, once invoked, is held until the stopping path is disjoint again with this "
            "factor on its length: standoff + ratio * d <= range (1.0: no hysteresis)")
    contingency_release_speed_mps: float = setting(
        1000.0, unit="m/s", allowed=Range(0.0, 1000.0),
        doc="... and only once the speed estimate is at or below this (1000: at any speed; a small value "
            "holds the contingency to standstill, as AEB functions that reset when the car stops)")
    contingency_decel_mps2: float = setting(
        BRAKE_DECEL_MAX_MPS2, unit="m/s^2", allowed=Range(0.0, BRAKE_DECEL_MAX_MPS2, low_open=True),
        doc="deceleration requested by the contingency: full braking, the DBC's full scale; the brake "
            "ECU saturates it at full pressure (ABS then limits slip)")
    decel_estimate_floor_mps2: float = setting(
        1.0, unit="m/s^2", allowed=Range(0.0, 15.0, low_open=True),
        doc="`adaptive` (our extension, ecu.core.decel_estimate): the estimate never drops below this")
    decel_estimate_time_constant_s: float = setting(
        0.1, unit="s", allowed=Range(0.0, math.inf, low_open=True),
        doc="time constant of the estimate's first-order update while there is evidence")
    decel_filter_time_constant_s: float = setting(
        0.2, unit="s", allowed=Range(0.0, math.inf, low_open=True),
        doc="time constant of the filter on the measured deceleration (speed derivative)")
    decel_settle_cycles: int = setting(
        50, unit="cycles", allowed=Range(0, 100_000),
        doc="braking must have been commanded this many cycles before it is evidence: the plant's brake "
            "dead time 0.1 s + 3 x its 0.12 s build-up, rounded up (fmu_plant/README.md)")
    driven_axle_load_share: float = setting(
        0.56, allowed=Range(0.0, 1.0, low_open=True),
        doc="share of the car's weight on the driven axle (plant: cg 1.2 m behind the front axle, "
            "wheelbase 2.7 m, so 1.5/2.7 = 0.56 static; the share falls while accelerating, which makes "
            "the traction evidence err low, the safe side)")
    decel_shortfall_mps2: float = setting(
        1.0, unit="m/s^2", allowed=Range(0.0, 15.0, low_open=True),
        doc="settled braking that falls this far short of the request is limited by the road")
    abs_slip_threshold: float = setting(
        0.1, allowed=Range(0.0, 1.0, low_open=True),
        doc="braking slip at or above which a wheel is at its friction limit (ABS regulating)")
    abs_slip_cycles: int = setting(3, unit="cycles", allowed=Range(1, 1000),
                                   doc="consecutive cycles of such slip before it counts as evidence (debounce)")
    decel_estimate_min_speed_mps: float = setting(3.0, unit="m/s", allowed=Range(0.0, 100.0),
                                                  doc="no evidence is drawn below this estimated speed")
    driven_axle: str = setting("front", allowed=NON_DRIVEN_WHEELS,
                               doc="the driven axle; the builtin plant is front-wheel driven")
    speed_slope_margin_mps2: float = setting(
        2.0, unit="m/s^2", allowed=Range(0.0, 50.0),
        doc="allowance on top of the physical limits in the speed estimate's slope limiter")
    brake_memory_s: float = setting(
        0.5, unit="s", allowed=Range(0.0, 10.0),
        doc="after braking was commanded, the speed estimate keeps treating the wheels as braked for "
            "this long: brake pressure outlives the command by the hydraulic dead time plus its decay "
            "(0.1 s + 3 x 0.12 s on the plant), and ABS-slipping wheels read slow until it has gone")
    moving_object_speed_mps: float = setting(
        0.5, unit="m/s", allowed=Range(0.0, 100.0),
        doc="an object faster than this (absolute, along our path) counts as moving")
    lead_region_speed_mps: float = setting(
        6.0, unit="m/s", allowed=Range(0.0, 100.0),
        doc="behind a closing object faster than this, our stopping path must also end short of the object's own "
            "stopping region (ecu.core.relative_stop): above the few m/s a standing object reads through the "
            "radar's latency and a tracker's lag (docs/investigations.md), so standing targets keep their results")
    standstill_speed_mps: float = setting(
        0.1, unit="m/s", allowed=Range(0.0, 10.0),
        doc="below this estimated speed the car counts as stopped (releases a held contingency)")
    vehicle_width_m: float = setting(
        1.815, unit="m", allowed=Range(0.0, 10.0, low_open=True),
        doc="relevance (ecu/core/relevance.py): our width, Euro NCAP's reference VUT (4.358 x 1.815 m)")
    path_margin_m: float = setting(
        1.0, unit="m", allowed=Range(0.0, 20.0),
        doc="an object counts as in our path while its centre is within vehicle_width_m / 2 plus this: "
            "half a car target's width (ISO 19206-3 GVT 1.712 m -> 0.856 m) plus 0.144 m allowance for "
            "lateral measurement error, i.e. any car body that overlaps ours is in the path")
    proximity_time_s: float = setting(
        1.0, unit="s", allowed=Range(0.0, 10.0),
        doc="moving objects (ecu/core/relative_stop.py): tightening's proximity margin is this long in "
            "time at the closing speed, capped at proximity_margin_m, floored at proximity_margin_min_m")
    proximity_margin_min_m: float = setting(1.0, unit="m", allowed=Range(0.0, 250.0, low_open=True),
                                            doc="floor of the moving-object proximity margin")
    track_confirm_reports: int = setting(
        3, unit="reports", allowed=Range(1, 100),
        doc="track confirmation (ecu/core/track_confirmation.py): an object starts an intervention only "
            "once this many consecutive ObjectTrack reports agree (1: every report confirms itself); "
            "3 reports of the DBC's 50 ms cycle confirm a track 100 ms after its first report")
    track_range_tolerance_m: float = setting(
        2.0, unit="m", allowed=Range(0.0, 250.0),
        doc="a report's range may differ this much from the previous report's advanced by the mean range "
            "rate: twice the difference of two reports each off by a radar's +-0.5 m range accuracy (an "
            "automotive 24 GHz radar's data sheet, ecu/README.md), 6.7 sigma at our noisiest scenario's 0.3 m")
    track_rate_tolerance_mps: float = setting(
        1.0, unit="m/s", allowed=Range(0.0, 200.0),
        doc="... its range rate this much from the previous report's, on top of the acceleration limit: "
            "with it (1 + 20 x 0.05 = 2 m/s per report) two reports each off by +-2 km/h (0.56 m/s, the "
            "same data sheet) agree")
    track_accel_limit_mps2: float = setting(
        20.0, unit="m/s^2", allowed=Range(0.0, 1000.0),
        doc="the largest relative acceleration of two road vehicles: each brakes or accelerates at most "
            "at about the dry-road friction limit, ~1 g (our plant's ABS peak: 8.9 m/s^2), so two stay "
            "below 2 g = 20 m/s^2")
    track_coast_s: float = setting(
        timeout_s("ObjectTrack"), unit="s", allowed=Range(0.0, math.inf, low_open=True),
        doc="a valid report continues the track of the last valid report at most this much older "
            "(reports of no object between them coast); default the DBC's ObjectTrack timeout, the "
            "age at which the ECU stops trusting a track at all")
    wheel_speeds_timeout_s: float = setting(
        timeout_s("WheelSpeeds"), unit="s", allowed=Range(0.0, math.inf, low_open=True),
        doc="WheelSpeeds reception timeout; at least its DBC cycle")
    driver_input_timeout_s: float = setting(
        timeout_s("DriverInput"), unit="s", allowed=Range(0.0, math.inf, low_open=True),
        doc="DriverInput reception timeout; at least its DBC cycle")
    object_timeout_s: float = setting(
        timeout_s("ObjectTrack"), unit="s", allowed=Range(0.0, math.inf, low_open=True),
        doc="ObjectTrack reception timeout; at least its DBC cycle")
    e2e_invalid_score: int = setting(
        5, allowed=Range(1, 5), doc="an input is invalid while its E2E validity score (can_dbc) is at or above this")
    fault_recovery_cycles: int = setting(
        10, unit="cycles", allowed=Range(1, 100_000),
        doc="consecutive all-valid cycles needed to leave FAULT (also at start-up)")
    wheel_slip_abs_mps: float = setting(
        2.0, unit="m/s", allowed=Range(0.0, 100.0),
        doc="plausibility (ecu.core.plausibility): spread allowed between the non-driven wheels, and "
            "between driven and non-driven ones without wheelspin, while not braking, absolute part "
            "(measured in the paper run: 1.53 m/s, 8.5 %)")
    wheel_slip_fraction: float = setting(
        0.3, allowed=Range(0.0, 1.0), doc="... and fraction of the fastest non-driven wheel")
    drive_memory_s: float = setting(
        0.75, unit="s", allowed=Range(0.0, 10.0),
        doc="after the accelerator was last pressed, the driven wheels may still spin up for this long: "
            "the powertrain's force decays with its first-order lag (plant: 0.25 s, fmu_plant/README.md), "
            "to 5 % after 3 time constants")
    driven_wheel_spinup_max_mps2: float = setting(
        290.0, unit="m/s^2", allowed=Range(0.0, 10_000.0),
        doc="while driving, the driven wheels' lead over the non-driven ones grows at most this fast: the "
            "whole drive force on the driven axle's inertia, F r^2 / J = 6000 N x (0.31 m)^2 / 2 kg m^2 "
            "= 288 m/s^2 (plant defaults, fmu_plant/README.md); measured at most 183 m/s^2 (paper run, "
            "friction 0.3)")
    radar_speed_tolerance_mps: float = setting(
        6.0, unit="m/s", allowed=Range(0.0, 100.0),
        doc="a valid object may close this much faster than our speed estimate (measured in the paper "
            "runs: +3.3 m/s, the ABS reference speed reading low plus the radar latency, while braking)")
    pedal_conflict_fraction: float = setting(0.5, allowed=Range(0.0, 1.0),
                                             doc="both pedals above this fraction at once is implausible")
    degraded_decel_fraction: float = setting(
        0.8, allowed=Range(0.0, 1.0, low_open=True),
        doc="degraded mode (ecu.core.degraded) plans with at most this fraction of peak_decel_mps2, the "
            "conservative strategy's: with a sensor lost it needs the margin (measured: 0.9 stopped 5 cm short)")

    steering_authority: bool = setting(
        False, doc="the EPS applies this ECU's SteeringOverride (a plant with a steering input): the stopping region "
                   "may choose steering paths (ecu.core.planar); without it the ECU brakes only. An ECU's "
                   "configuration (ecu.EcuConfig) takes it from its equipment: true exactly with planar_steering")
    steering_ratio: float = setting(
        16.0, allowed=Range(1.0, 50.0),
        doc="steering-wheel angle / road-wheel angle, for the driver's road-wheel angle from DriverInput: the builtin "
            "plant's 16 (passenger cars 12-20:1, fmu_plant/README.md)")
    track_position_sigma_m: float = setting(
        0.17, unit="m", allowed=Range(0.0, 10.0),
        doc="standard deviation of a RadarTrack's position (the contract carries none): the +-0.5 m range accuracy "
            "of the radar data sheet (track_range_tolerance_m) taken as 3 sigma; the region inflates objects by 3 sigma")
    track_speed_tolerance_mps: float = setting(
        0.5, unit="m/s", allowed=Range(0.0, 20.0),
        doc="the stopping region counts a RadarTrack as moving above moving_object_speed_mps plus this: its relative "
            "velocity is the radar's, a radar latency old (0.1 s), while the ego's speed is this cycle's; at the "
            "driver's 5 m/s^2 they are 0.5 m/s apart (measured: a car parked beside a curve read 0.51 m/s); and "
            "a moving track's heading is this uncertain when its box is placed (ecu/core/region/objects.py)")
    lane_width_m: float = setting(
        3.5, unit="m", allowed=Range(2.0, 6.0, low_open=True),
        doc="the ECU perceives no lanes (none on the contract): it assumes its own lane this wide, centred on it, "
            "following its current curvature (the bird's-eye catalogues' 3.5 m lanes)")
    free_lanes_left: int = setting(
        1, allowed=Range(0, 4),
        doc="... and this many lanes to its left that a steering path may enter when no track's centre lies in them "
            "(right-hand traffic: a two-lane road's other lane); beyond them is off the road (UN R79 ESF)")
    free_lanes_right: int = setting(0, allowed=Range(0, 4),
                                    doc="... and this many to its right (0: the road's edge bounds our lane)")
    way_out: str = setting(
        "none", allowed=("none", "right_of_way", "reciprocal"),
        doc="the way out of a crossing's deadlock (ecu.core.region.crossing.WAY_OUT_RULES): which crossing vehicles "
            "tightening bounds the throttle against; none: every one (the plain method); right_of_way: only those "
            "from the right (Vienna Convention 1968, art. 18(4)(a)), and, when our path turns into the next lane, "
            "the vehicle in it (art. 14(1), ecu.core.region.lane_change); reciprocal: only those ORCA's split of "
            "responsibility gives us to slow for (ecu.core.region.reciprocal); the contingency holds against all")
    way_out_patience_s: float = setting(
        1.5, unit="s", allowed=Range(0.0, 600.0),
        doc="right_of_way: slow this long with something near, the car takes its turn (ecu.core.way_out)")
    way_out_seed: int = setting(
        0, allowed=Range(0, 2**64 - 1),  # a fleet gives a scenario seed (< 2^63) plus the vehicle's index
        doc="right_of_way: seeds the draws of a car's wait after it gives back a turn it took with another car at a "
            "narrowing (ecu.core.way_out, backing off); a fleet gives each car its own seed")
    way_out_slow_speed_mps: float = setting(3.0, unit="m/s", allowed=Range(0.0, 20.0),
                                            doc="right_of_way: below this speed a car counts as waiting (above "
                                                "the crossing dance's recoveries, at most 2.5 m/s in crd fleet "
                                                "four_way, so a car that dances counts as waiting)")
    way_out_path_m: float = setting(
        30.0, unit="m", allowed=Range(0.0, 500.0),
        doc="right_of_way: a car given way to is assumed to go on this far along its velocity (its way through the "
            "crossing: do not enter a crossing where one would have to stop, Vienna Convention 1968, art. 18(2))")

    narrowing_wait_m: float = setting(
        20.0, unit="m", allowed=Range(0.0, 200.0),
        doc="right_of_way at a narrowing (ecu.core.region.narrowing, StVO section 6): the car that lets an oncoming "
            "one through stops this far before the narrowing's entry, so that the other, leaving it in the middle "
            "of the road, is back on its side before it passes us (half a lane, 1.75 m, in a 15 m sine at 30 km/h, "
            "2.7 m/s^2 of lateral acceleration, plus its stopping path at 30 km/h, 7 m; argued, not sourced)")

    model_decel_mps2: float = field(init=False, repr=False, compare=False)
    model_decel_fraction: float = field(init=False, repr=False, compare=False)
    #: the strategy's rules (:mod:`ecu.core.strategies`): what it decides each cycle
    strategy_rules: Strategy = field(init=False, repr=False, compare=False)
    strategy_code: int = field(init=False, repr=False, compare=False)
    #: t_h = cycle_s + actuation_latency_s: how long the driver's command is assumed held (s). A field set
    #: once here, not a property: read up to four times a cycle, a property call cost ~0.1 µs each (measured).
    hold_time_s: float = field(init=False, repr=False, compare=False)
    #: the stopping region's :class:`~ecu.core.region.RegionParams` (:func:`ecu.core.region.region_params`), built
    #: once (typed Any: that module imports this one, and the settings loader resolves every field's type)
    region: Any = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # imported here: the strategies' modules import this one's module (decel_estimate: NON_DRIVEN_WHEELS)
        from .strategies import REGISTRY

        rules = REGISTRY.get(self.strategy)
        if rules is None:
            raise ValueError(f"strategy: expected one of {list(REGISTRY)}, got {self.strategy!r}")
        fraction = rules.decel_fraction(self)
        object.__setattr__(self, "strategy_rules", rules)
        object.__setattr__(self, "model_decel_fraction", fraction)
        object.__setattr__(self, "model_decel_mps2", fraction * self.peak_decel_mps2)
        object.__setattr__(self, "strategy_code", STRATEGIES[self.strategy])
        object.__setattr__(self, "hold_time_s", self.cycle_s + self.actuation_latency_s)
        from .region.params import region_params  # here: the region's parameters import this module

        object.__setattr__(self, "region", region_params(
            self, moving_object_speed_mps=self.moving_object_speed_mps + self.track_speed_tolerance_mps))
