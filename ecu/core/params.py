"""Parameters of the pure ECU core: one frozen dataclass, every number a field.

Units are SI and named in the field. ``strategy`` names one of the registry
:data:`ecu.core.strategies.REGISTRY` (the DBC's ``EcuStatus.Strategy``
values: the paper's ``none``, ``conservative`` and ``tightening``, Johnson
2019 section III, and our ``adaptive``). The derived fields are computed once
at construction so the cycle does no table lookups: ``strategy_rules`` (the strategy's
module), ``strategy_code`` (its DBC value), ``hold_time_s`` and, with the
strategy's ``strategy_rules.decel_fraction(params)``,

    model_decel_mps2 = fraction(strategy) * peak_decel_mps2

Range checks live in :mod:`ecu.config` (the one loader); the core trusts its
parameters. Defaults that are facts of the CAN contract (the cycle, the
reception timeouts, the full-scale deceleration request) are read from the
DBC through :mod:`can_dbc.contract`; the loader refuses values that contradict it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from can_dbc.contract import BRAKE_DECEL_MAX_MPS2, ECU_CYCLE_S, STRATEGY_CODES, timeout_s

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


@dataclass(frozen=True, slots=True)
class CoreParams:
    """Everything the core's arithmetic depends on (defaults are the lead's starting values)."""

    strategy: str = "tightening"
    cycle_s: float = ECU_CYCLE_S
    #: declared delay from our frame to the brake/powertrain acting on it.
    actuation_latency_s: float = 0.1
    #: peak achievable deceleration of the vehicle on dry road.
    peak_decel_mps2: float = 9.0
    none_decel_fraction: float = 0.9
    conservative_decel_fraction: float = 0.8
    tightening_decel_fraction: float = 0.9
    #: the stopping path must end at least this far before the object.
    standoff_m: float = 2.0
    #: acceleration attributed to a fully pressed accelerator pedal.
    driver_max_accel_mps2: float = 3.0
    #: constraint tightening: proximity grows from 0 to 1 as the nominal stopping
    #: path's margin to the standoff shrinks from this distance to zero.
    proximity_margin_m: float = 10.0
    #: a contingency, once invoked, is held until the stopping path is disjoint again with
    #: this factor on its length: ``standoff + ratio * d <= range`` (1.0: no hysteresis).
    contingency_release_ratio: float = 1.0
    #: ... and only once the speed estimate is at or below this (1000: at any speed; a small
    #: value holds the contingency to standstill, as AEB functions that reset when the car stops).
    contingency_release_speed_mps: float = 1000.0
    #: deceleration requested by the contingency: full braking, the DBC's full
    #: scale; the brake ECU saturates it at full pressure (ABS then limits slip).
    contingency_decel_mps2: float = BRAKE_DECEL_MAX_MPS2
    #: ``adaptive`` (our extension, :mod:`ecu.core.decel_estimate`): the estimate never drops below this.
    decel_estimate_floor_mps2: float = 1.0
    #: time constant of the estimate's first-order update while there is evidence.
    decel_estimate_time_constant_s: float = 0.1
    #: time constant of the filter on the measured deceleration (speed derivative).
    decel_filter_time_constant_s: float = 0.2
    #: braking must have been commanded this many cycles before it is evidence: the plant's
    #: brake dead time 0.1 s + 3 x its 0.12 s build-up, rounded up (fmu_plant/README.md).
    decel_settle_cycles: int = 50
    #: share of the car's weight on the driven axle (plant: cg 1.2 m behind the front axle,
    #: wheelbase 2.7 m, so 1.5/2.7 = 0.56 static; the share falls while accelerating, which
    #: makes the traction evidence err low, the safe side).
    driven_axle_load_share: float = 0.56
    #: settled braking that falls this far short of the request is limited by the road.
    decel_shortfall_mps2: float = 1.0
    #: braking slip at or above which a wheel is at its friction limit (ABS regulating).
    abs_slip_threshold: float = 0.1
    #: consecutive cycles of such slip before it counts as evidence (debounce).
    abs_slip_cycles: int = 3
    #: no evidence is drawn below this estimated speed.
    decel_estimate_min_speed_mps: float = 3.0
    #: "front", "rear" or "all"; the plant is front-wheel driven.
    driven_axle: str = "front"
    #: allowance on top of the physical limits in the speed estimate's slope limiter.
    speed_slope_margin_mps2: float = 2.0
    #: after braking was commanded, the speed estimate keeps treating the wheels as
    #: braked for this long: brake pressure outlives the command by the hydraulic
    #: dead time plus its decay (0.1 s + 3 x 0.12 s on the plant), and ABS-slipping
    #: wheels read slow until it has gone.
    brake_memory_s: float = 0.5
    #: an object faster than this (absolute, along our path) counts as moving.
    moving_object_speed_mps: float = 0.5
    #: below this estimated speed the car counts as stopped (releases a held contingency).
    standstill_speed_mps: float = 0.1
    #: relevance (ecu/core/relevance.py): our width, Euro NCAP's reference VUT (4.358 x 1.815 m).
    vehicle_width_m: float = 1.815
    #: an object counts as in our path while its centre is within vehicle_width_m / 2 plus this
    #: (m): half a car target's width (ISO 19206-3 GVT 1.712 m -> 0.856 m) plus 0.144 m allowance
    #: for lateral measurement error, i.e. any car body that overlaps ours is in the path.
    path_margin_m: float = 1.0
    #: moving objects (ecu/core/relative_stop.py): tightening's proximity margin is this long in
    #: time at the closing speed, capped at proximity_margin_m, floored at proximity_margin_min_m.
    proximity_time_s: float = 1.0
    proximity_margin_min_m: float = 1.0
    wheel_speeds_timeout_s: float = timeout_s("WheelSpeeds")
    driver_input_timeout_s: float = timeout_s("DriverInput")
    object_timeout_s: float = timeout_s("ObjectTrack")
    #: an input is invalid while its E2E validity score (can_dbc) is at or above this.
    e2e_invalid_score: int = 5
    #: consecutive all-valid cycles needed to leave FAULT (also at start-up).
    fault_recovery_cycles: int = 10
    #: plausibility (ecu.core.plausibility): wheel spread allowed while not braking, absolute
    #: part and fraction of the fastest wheel (measured in the paper run: 1.53 m/s, 8.5 %).
    wheel_slip_abs_mps: float = 2.0
    wheel_slip_fraction: float = 0.3
    #: a valid object may close this much faster than our speed estimate (measured in the paper
    #: runs: +3.3 m/s, the ABS reference speed reading low plus the radar latency, while braking).
    radar_speed_tolerance_mps: float = 6.0
    #: both pedals above this fraction at once is implausible.
    pedal_conflict_fraction: float = 0.5
    #: degraded mode (ecu.core.degraded) plans with at most this fraction of peak_decel, the
    #: conservative strategy's: with a sensor lost it needs the margin (measured: 0.9 stopped 5 cm short).
    degraded_decel_fraction: float = 0.8

    model_decel_mps2: float = field(init=False, repr=False, compare=False)
    model_decel_fraction: float = field(init=False, repr=False, compare=False)
    #: the strategy's rules (:mod:`ecu.core.strategies`): what it decides each cycle
    strategy_rules: Strategy = field(init=False, repr=False, compare=False)
    strategy_code: int = field(init=False, repr=False, compare=False)
    #: t_h = cycle_s + actuation_latency_s: how long the driver's command is assumed held (s). A field set
    #: once here, not a property: read up to four times a cycle, a property call cost ~0.1 µs each (measured).
    hold_time_s: float = field(init=False, repr=False, compare=False)

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
