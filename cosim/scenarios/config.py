"""The scenario as frozen dataclasses: one per TOML section.

Every field carries its unit in its name and its allowed range in
``metadata["range"]`` (closed interval) or ``metadata["choices"]``; the loader
(:mod:`cosim.scenarios.loader`) enforces both and rejects unknown keys.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import datetime
from types import MappingProxyType
from typing import Mapping

from can_dbc.contract import ECU_CYCLE_S, STRATEGIES, cycle_time_s, timeout_s

OBJECT_TRACK_PERIOD_S = cycle_time_s("ObjectTrack")  # the contract's radar cycle (DBC GenMsgCycleTime 50 ms)
#: the paper's three strategies; the DBC's ``VAL_`` adds our extension ``adaptive`` (issue 14).
PAPER_STRATEGIES = ("none", "conservative", "tightening")
#: ``[scenario] start_time`` default: the start of 2020, UTC. A fixed date keeps the logs'
#: headers deterministic; any date from 1990 on works (BLF treats earlier ones as unset).
DEFAULT_START_TIME = "2020-01-01T00:00:00+00:00"


def _r(lo: float, hi: float) -> dict:
    return {"range": (lo, hi)}


def _c(*choices: object) -> dict:
    return {"choices": choices}


@dataclass(frozen=True)
class ScenarioSection:
    """``[scenario]``: name, simulated duration (s), plant step (s), seed, start time.

    ``start_time`` is the absolute time of t = 0 (ISO 8601 with a UTC offset, or a
    TOML offset date-time); the CAN logs' headers carry it (:mod:`cosim.results.can_logs`).
    """

    name: str = "scenario"
    duration_s: float = field(default=30.0, metadata=_r(0.01, 3600.0))
    step_s: float = field(default=0.001, metadata=_r(1e-4, ECU_CYCLE_S))
    seed: int = field(default=0, metadata=_r(0, 2**63 - 1))
    start_time: str = field(default=DEFAULT_START_TIME, metadata={"datetime": True})

    @property
    def start_datetime(self) -> datetime:
        """``start_time`` as an aware :class:`datetime.datetime`."""
        return datetime.fromisoformat(self.start_time)


@dataclass(frozen=True)
class SignalMap:
    """One role of ``[plant.inputs]``/``[plant.outputs]`` mapped to FMU variables.

    Outputs: ``si = fmu_value * scale + offset``.
    Inputs: ``fmu_value = role_value * scale + offset``.
    ``names`` has one entry, except ``wheel_speeds`` (1 to 4 names, rad/s after scaling).
    """

    role: str
    names: tuple[str, ...]
    scale: float = 1.0
    offset: float = 0.0


INPUT_ROLES = ("throttle", "brake", "accel_command", "road_friction")
OUTPUT_ROLES = ("position", "speed", "accel", "wheel_speeds")

BUILTIN_INPUTS = (
    SignalMap("throttle", ("throttle",)),
    SignalMap("brake", ("brake",)),
    SignalMap("road_friction", ("road_friction",)),
)
BUILTIN_OUTPUTS = (
    SignalMap("position", ("x",)),
    SignalMap("speed", ("v",)),
    SignalMap("accel", ("a",)),
    SignalMap("wheel_speeds", ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr")),
)

INITIAL_ROLES = ("speed",)
BUILTIN_INITIAL = (SignalMap("speed", ("v0",)),)


@dataclass(frozen=True)
class PlantConfig:
    """``[plant]``: which FMU, its parameters and how its variables map to roles.

    ``accel_gain_mps2``/``brake_gain_mps2`` drive an ``accel_command`` FMU:
    ``accel_command = throttle * accel_gain_mps2 - brake * brake_gain_mps2`` (m/s²).
    ``wheel_radius_m`` converts wheel speeds (rad/s → m/s) and derives them
    from the speed when the FMU has none. ``front_bumper_offset_m`` is the
    front bumper's position relative to the FMU's position output.
    ``isolation``: where the FMU runs (``cosim.world.plant.open_plant``);
    ``step_timeout_s``: with ``process``, the longest any FMU call may take
    before the run stops with an error naming the time.
    """

    fmu: str = "builtin"
    fmi_version: int = field(default=3, metadata=_c(2, 3))
    road_friction: float = field(default=1.0, metadata=_r(0.0, 1.5))
    wheel_radius_m: float = field(default=0.31, metadata=_r(0.05, 2.0))
    front_bumper_offset_m: float = field(default=0.0, metadata=_r(-10.0, 10.0))
    isolation: str = field(default="auto", metadata=_c("auto", "inprocess", "process"))
    step_timeout_s: float = field(default=5.0, metadata=_r(0.01, 3600.0))
    accel_gain_mps2: float = field(default=3.0, metadata=_r(0.0, 20.0))
    brake_gain_mps2: float = field(default=9.0, metadata=_r(0.0, 20.0))
    #: speed at t = 0 (m/s), set through the ``[plant.initial]`` ``speed`` parameter
    #: (builtin: ``v0``); 0 leaves the FMU's own start value.
    initial_speed_mps: float = field(default=0.0, metadata=_r(0.0, 80.0))
    #: body of the vehicle for contact (collision needs longitudinal AND lateral
    #: overlap); defaults: Euro NCAP's reference VUT, 4.358 x 1.815 m.
    length_m: float = field(default=4.358, metadata=_r(0.5, 30.0))
    width_m: float = field(default=1.815, metadata=_r(0.5, 5.0))
    parameters: Mapping[str, float | bool] = field(default_factory=lambda: MappingProxyType({}))
    inputs: tuple[SignalMap, ...] = BUILTIN_INPUTS
    outputs: tuple[SignalMap, ...] = BUILTIN_OUTPUTS
    initial: tuple[SignalMap, ...] = BUILTIN_INITIAL

    def input_map(self, role: str) -> SignalMap | None:
        return next((m for m in self.inputs if m.role == role), None)

    def output_map(self, role: str) -> SignalMap | None:
        return next((m for m in self.outputs if m.role == role), None)


@dataclass(frozen=True)
class DriverConfig:
    """``[driver]``: the guidance model.

    ``full_throttle``: accelerator at ``accel_pedal_pct`` always (the paper's distracted driver).
    ``cruise``: P control on speed, ``pedal% = gain_pct_per_mps * (set_speed_mps - v)``,
    positive to the accelerator, negative to the brake.
    ``hold_speed``: PI control on speed (no steady-state error), accelerator only
    (never brakes), optional release after a ``release_drop_mps`` drop
    (:func:`cosim.world.driver_models.hold_speed`).
    ``scripted``: ``points`` = rows ``[at, accel_pct, brake_pct]`` with ``at`` in s
    (``over = "time"``) or m (``over = "position"``), linearly interpolated, held at the ends.
    """

    model: str = field(default="full_throttle",
                       metadata=_c("full_throttle", "cruise", "scripted", "hold_speed"))
    accel_pedal_pct: float = field(default=100.0, metadata=_r(0.0, 100.0))
    set_speed_mps: float = field(default=20.0, metadata=_r(0.0, 80.0))
    gain_pct_per_mps: float = field(default=20.0, metadata=_r(0.0, 1000.0))
    #: ``hold_speed`` only: integral gain (% per m of accumulated speed error).
    integral_gain_pct_per_m: float = field(default=10.0, metadata=_r(0.0, 1000.0))
    #: ``hold_speed`` only: release the accelerator for good once the speed is this far
    #: below the set speed (Euro NCAP robot: 5 km/h); 0 = never release.
    release_drop_mps: float = field(default=0.0, metadata=_r(0.0, 80.0))
    over: str = field(default="time", metadata=_c("time", "position"))
    points: tuple[tuple[float, float, float], ...] = ()


@dataclass(frozen=True)
class ObjectConfig:
    """``[object]`` or one of ``[[objects]]``: a body on or beside the path.

    ``position_m`` is the object's rear at t = 0 on the path; it occupies
    ``[rear, rear + length_m]`` along the path and ``lateral_m ± width_m/2``
    across it (left positive), and moves at ``speed_mps`` along the path.
    Longitudinal profile: constant speed, or braking at ``brake_decel_mps2``
    (reached linearly within ``brake_ramp_s``) down to ``brake_to_speed_mps``,
    starting at ``brake_at_s`` or when the ego's gap first falls to
    ``brake_at_gap_m`` (0 decel = never brakes). Lateral motion: at
    ``lateral_speed_mps`` toward ``lateral_end_m``, starting at ``lateral_at_s``
    or at ``lateral_at_gap_m`` (cut-in, cut-out). Equations:
    :mod:`cosim.world.scene_motion`.
    """

    enabled: bool = True
    name: str = "object"
    position_m: float = field(default=225.0, metadata=_r(-1e5, 1e5))
    speed_mps: float = field(default=0.0, metadata=_r(-80.0, 80.0))
    length_m: float = field(default=1.8, metadata=_r(0.0, 50.0))
    width_m: float = field(default=0.6, metadata=_r(0.0, 10.0))
    lateral_m: float = field(default=0.0, metadata=_r(-20.0, 20.0))
    brake_decel_mps2: float = field(default=0.0, metadata=_r(0.0, 15.0))
    brake_ramp_s: float = field(default=0.0, metadata=_r(0.0, 10.0))
    brake_to_speed_mps: float = field(default=0.0, metadata=_r(0.0, 80.0))
    brake_at_s: float | None = field(default=None, metadata=_r(0.0, 3600.0))
    brake_at_gap_m: float | None = field(default=None, metadata=_r(0.0, 1e4))
    lateral_speed_mps: float = field(default=0.0, metadata=_r(0.0, 10.0))
    lateral_end_m: float | None = field(default=None, metadata=_r(-20.0, 20.0))
    lateral_at_s: float | None = field(default=None, metadata=_r(0.0, 3600.0))
    lateral_at_gap_m: float | None = field(default=None, metadata=_r(0.0, 1e4))


@dataclass(frozen=True)
class RadarConfig:
    """``[radar]``: range (front bumper → object rear) and range rate every 50 ms.

    ``latency_s`` is rounded to whole ECU cycles; noise is zero-mean Gaussian
    with the given standard deviations from a generator seeded by
    ``[scenario] seed``; beyond ``max_range_m`` or on a dropout (probability
    per update) the track reports ``ObjectValid = 0``.
    """

    latency_s: float = field(default=0.0, metadata=_r(0.0, 1.0))
    range_noise_std_m: float = field(default=0.0, metadata=_r(0.0, 10.0))
    range_rate_noise_std_mps: float = field(default=0.0, metadata=_r(0.0, 10.0))
    max_range_m: float = field(default=200.0, metadata=_r(1.0, 250.0))
    dropout_probability: float = field(default=0.0, metadata=_r(0.0, 1.0))
    #: full horizontal field of view (deg); an object whose nearest rear corner is
    #: outside ``±fov/2`` of the bore sight is not seen. Default ±45°: the near-range
    #: beam of a mid-range automotive radar (class value, [M]).
    field_of_view_deg: float = field(default=90.0, metadata=_r(1.0, 180.0))


@dataclass(frozen=True)
class GatewayConfig:
    """``[gateway]``: the brake/powertrain ECU that applies ``SafetyOverride``.

    ``brake_full_decel_mps2`` maps the ECU's deceleration request to a brake
    command: ``brake = min(1, request / brake_full_decel_mps2)``. Default
    12 m/s² = the builtin plant's ``max_brake_force / mass`` = 18000 N / 1500 kg.
    ``override_timeout_s``: silence (or an invalid E2E score) longer than this
    falls back to the driver's commands alone.
    """

    brake_full_decel_mps2: float = field(default=12.0, metadata=_r(1.0, 30.0))
    override_timeout_s: float = field(default=timeout_s("SafetyOverride"), metadata=_r(ECU_CYCLE_S, 1.0))


@dataclass(frozen=True)
class EcuSection:
    """``[ecu]``: the strategy and any ``EcuConfig`` parameter (checked by ``EcuConfig.from_dict``)."""

    strategy: str = field(default="tightening", metadata=_c(*STRATEGIES))
    parameters: Mapping[str, object] = field(default_factory=lambda: MappingProxyType({}))


#: events ``[checks] expect_events`` may name: the faults that otherwise make a run exit 4
#: (``cosim.results.events.FAULT_EVENTS``)
EXPECTABLE_EVENTS = ("ecu_lost", "second_ecu", "auth_failure", "ecu_security_fault")


@dataclass(frozen=True)
class ChecksConfig:
    """``[checks]``: expectations on the run's metrics; ``None`` = not checked.

    ``expect_events``: fault events this scenario provokes on purpose (e.g. ``["ecu_lost"]``):
    each must occur (else the check fails, exit 3), and does not make the run exit 4.
    """

    no_collision: bool | None = None
    min_gap_m: float | None = field(default=None, metadata=_r(-1e5, 1e5))
    max_impact_speed_mps: float | None = field(default=None, metadata=_r(0.0, 200.0))
    min_contingency_invocations: int | None = field(default=None, metadata=_r(0, 10**6))
    max_contingency_invocations: int | None = field(default=None, metadata=_r(0, 10**6))
    expect_events: tuple[str, ...] = ()


@dataclass(frozen=True)
class EndConfig:
    """``[end]``: conditions that end the run early (contact and ``duration_s`` always do).

    ``standstill``: the ego's speed falls to ``standstill_speed_mps`` after having been
    above it. ``matched_speed``: the ego's speed falls to that of the nearest object
    ahead in its path after having been ``matched_speed_margin_mps`` above it (Euro
    NCAP's end of a longitudinal test: the VUT reaches the target's speed).
    """

    standstill: bool = False
    matched_speed: bool = False
    standstill_speed_mps: float = field(default=0.01, metadata=_r(0.0, 5.0))
    matched_speed_margin_mps: float = field(default=0.5, metadata=_r(0.0, 10.0))


@dataclass(frozen=True)
class Scenario:
    """A whole scenario file (``objects``: the ``[[objects]]`` array; then ``object`` is disabled)."""

    scenario: ScenarioSection = ScenarioSection()
    plant: PlantConfig = PlantConfig()
    driver: DriverConfig = DriverConfig()
    object: ObjectConfig = ObjectConfig()
    radar: RadarConfig = RadarConfig()
    gateway: GatewayConfig = GatewayConfig()
    ecu: EcuSection = EcuSection()
    checks: ChecksConfig = ChecksConfig()
    objects: tuple[ObjectConfig, ...] = ()
    end: EndConfig = EndConfig()

    def scene_objects(self) -> tuple[ObjectConfig, ...]:
        """Every enabled object: ``[[objects]]`` if given, else the single ``[object]``."""
        objs = self.objects or (self.object,)
        return tuple(o for o in objs if o.enabled)
