"""The scenario as frozen dataclasses: one per TOML section.

Every key is declared once, on its field (:func:`ecu.settings.setting`: type,
unit in the name and the declaration, range or choices, default, doc); the
loader (:mod:`cosim.scenarios.loader`, through :func:`ecu.settings.load`)
enforces them and rejects unknown keys, and the reference page
(``docs/scenario-reference.md``, :mod:`cosim.scenarios.reference`) is rendered
from them. ``[ecu]`` is :class:`ecu.EcuConfig` itself, declared the same way.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from types import MappingProxyType
from typing import Mapping

from can_dbc.contract import ECU_CYCLE_S, STRATEGIES, cycle_time_s, timeout_s  # STRATEGIES: for importers
from ecu.config import EcuConfig
from ecu.equipment import equipment_for
from ecu.settings import Range, setting

from ..world.targets import TARGET_CLASSES
from .kinds import FMU_START_VALUES, POINTS, START_TIME, SignalMap, event_names, signal_maps
from .planar_config import CrossingConfig, PoseConfig, RoadConfig, RoadPoseConfig, SteeringConfig, TrajectoryConfig

OBJECT_TRACK_PERIOD_S = cycle_time_s("ObjectTrack")  # the contract's radar cycle (DBC GenMsgCycleTime 50 ms)
#: the paper's three strategies, the one list of them (``crd matrix``'s default, the runs the paper's
#: claims need); the DBC's ``VAL_`` adds our extension ``adaptive`` (issue 14).
PAPER_STRATEGIES = ("none", "conservative", "tightening")
#: ``[scenario] start_time`` default: the start of 2020, UTC. A fixed date keeps the logs'
#: headers deterministic; any date from 1990 on works (BLF treats earlier ones as unset).
DEFAULT_START_TIME = "2020-01-01T00:00:00+00:00"


@dataclass(frozen=True)
class ScenarioSection:
    """``[scenario]``: name, simulated duration, plant step, seed, start time."""

    name: str = setting("scenario", doc="the scenario's name (reports, plots)")
    duration_s: float = setting(30.0, unit="s", allowed=Range(0.01, 3600.0),
                                doc="simulated time; the run ends here unless contact or [end] ends it first")
    step_s: float = setting(0.001, unit="s", allowed=Range(1e-4, ECU_CYCLE_S),
                            doc=f"plant step; must divide the {ECU_CYCLE_S} s ECU cycle")
    seed: int = setting(0, allowed=Range(0, 2**63 - 1), doc="seeds every random source of the run (radar noise, dropouts)")
    start_time: str = setting(DEFAULT_START_TIME, kind=START_TIME,
                              doc="absolute time of t = 0 (ISO 8601 with a UTC offset, or a TOML offset "
                                  "date-time); the CAN logs' headers carry it (cosim.results.can_logs)")

    @property
    def start_datetime(self) -> datetime:
        """``start_time`` as an aware :class:`datetime.datetime`."""
        return datetime.fromisoformat(self.start_time)


#: ``steer_request`` (rad): the ECU's road-wheel angle overlay as the steering gateway passes it on
#: (SteeringOverride); optional: a plant without it steers by the driver's wheel alone
INPUT_ROLES = ("throttle", "brake", "accel_command", "road_friction", "steering_wheel_angle", "steer_request")
#: the plane: ``y`` (m) and ``yaw`` (rad) of the point whose ``position`` is mapped, ``yaw_rate`` (rad/s), and
#: ``vx``, ``vy`` (m/s), that point's velocity in the vehicle frame; a plant without them stays on the line
POSE_OUTPUT_ROLES = ("y", "yaw", "yaw_rate", "vx", "vy")
#: ``ax``, ``ay`` (m/s²): that point's acceleration in the vehicle frame, as the ESC's sensor reads it; a plant
#: without them reports its ``accel`` and ``vx * yaw_rate`` (the steady-state lateral acceleration)
PLANAR_OUTPUT_ROLES = (*POSE_OUTPUT_ROLES, "ax", "ay")
OUTPUT_ROLES = ("position", "speed", "accel", "wheel_speeds", *PLANAR_OUTPUT_ROLES)

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

INITIAL_ROLES = ("speed", "y", "yaw")
BUILTIN_INITIAL = (SignalMap("speed", ("v0",)),)
#: the builtin plant's planar maps, added by the loader to a planar scenario only (a 1-D scenario's
#: resolved file stays as it was; with the wheel straight the plant's y and yaw stay exactly 0)
BUILTIN_PLANAR_INPUTS = (SignalMap("steering_wheel_angle", ("steering_wheel_angle",)),
                         SignalMap("steer_request", ("steer_request",)))
BUILTIN_PLANAR_OUTPUTS = tuple(SignalMap(role, (role,)) for role in PLANAR_OUTPUT_ROLES)
BUILTIN_PLANAR_INITIAL = (SignalMap("y", ("y0",)), SignalMap("yaw", ("yaw0",)))


@dataclass(frozen=True)
class PlantConfig:
    """``[plant]``: which FMU, its parameters and how its variables map to roles.

    A third-party FMU needs ``[plant.inputs]`` (``throttle`` and ``brake``, or
    ``accel_command``) and ``[plant.outputs]`` (at least ``position`` and ``speed``);
    the builtin plant has default maps, and a role given replaces its default.
    Inputs: ``fmu_value = role_value * scale + offset``; outputs:
    ``si = fmu_value * scale + offset``.
    """

    fmu: str = setting("builtin", doc="\"builtin\" (our plant, fmu_plant/) or the path of an FMU, "
                                      "relative to the scenario file")
    fmi_version: int = setting(3, allowed=(2, 3), doc="FMI version of the builtin plant's build")
    road_friction: float = setting(1.0, allowed=Range(0.0, 1.5), doc="road friction coefficient (1.0: dry asphalt)")
    wheel_radius_m: float = setting(0.31, unit="m", allowed=Range(0.05, 2.0),
                                    doc="converts wheel speeds (rad/s -> m/s); derives them from the speed "
                                        "when the FMU has none")
    front_bumper_offset_m: float = setting(0.0, unit="m", allowed=Range(-10.0, 10.0),
                                           doc="the front bumper's position relative to the FMU's position "
                                               "output (0: the builtin plant's x is its front bumper)")
    isolation: str = setting("auto", allowed=("auto", "inprocess", "process"),
                             doc="where the FMU runs (cosim.world.plant.open_plant)")
    step_timeout_s: float = setting(5.0, unit="s", allowed=Range(0.01, 3600.0),
                                    doc="with isolation = \"process\": the longest any FMU call may take before "
                                        "the run stops with an error naming the time")
    accel_gain_mps2: float = setting(3.0, unit="m/s^2", allowed=Range(0.0, 20.0),
                                     doc="an accel_command FMU gets throttle * accel_gain_mps2 - brake * "
                                         "brake_gain_mps2")
    brake_gain_mps2: float = setting(9.0, unit="m/s^2", allowed=Range(0.0, 20.0), doc="see accel_gain_mps2")
    initial_speed_mps: float = setting(0.0, unit="m/s", allowed=Range(0.0, 80.0),
                                       doc="speed at t = 0, set through the [plant.initial] speed parameter "
                                           "(builtin: v0); 0 leaves the FMU's own start value")
    length_m: float = setting(4.358, unit="m", allowed=Range(0.5, 30.0),
                              doc="body length for contact (Euro NCAP's reference VUT: 4.358 x 1.815 m)")
    width_m: float = setting(1.815, unit="m", allowed=Range(0.5, 5.0),
                             doc="body width; contact needs longitudinal AND lateral overlap")
    parameters: Mapping[str, bool | int | float | str] = setting(
        factory=lambda: MappingProxyType({}), kind=FMU_START_VALUES,
        doc="FMU start values by parameter name (the FMU defines the names; checked against its model "
            "description when the plant opens), e.g. brake_dead_time = 0.15")
    inputs: tuple[SignalMap, ...] = setting(BUILTIN_INPUTS, kind=signal_maps(INPUT_ROLES),
                                            doc="[plant.inputs]: the FMU's input variables by role")
    outputs: tuple[SignalMap, ...] = setting(BUILTIN_OUTPUTS, kind=signal_maps(OUTPUT_ROLES),
                                             doc="[plant.outputs]: the FMU's output variables by role")
    initial: tuple[SignalMap, ...] = setting(BUILTIN_INITIAL, kind=signal_maps(INITIAL_ROLES),
                                             doc="[plant.initial]: the FMU parameters that initial_speed_mps, "
                                                 "initial_y_m and initial_yaw_rad set")
    initial_y_m: float | None = setting(None, unit="m", allowed=Range(-1e5, 1e5),
                                        doc="planar: y of the point the plant's pose follows (builtin: the centre of "
                                            "gravity) at t = 0, through [plant.initial] y (builtin: y0)")
    initial_yaw_rad: float | None = setting(None, unit="rad", allowed=Range(-6.3, 6.3),
                                            doc="planar: heading at t = 0, through [plant.initial] yaw (builtin: yaw0)")
    cg_to_front_m: float | None = setting(None, unit="m", allowed=Range(0.0, 30.0),
                                          doc="planar: from the point the plant's pose follows (builtin: the centre of "
                                              "gravity, about which it turns) forward to the front bumper; unset: "
                                              "length_m / 2, the box centred on it (CommonRoad's convention)")

    def initial_values(self) -> list[tuple[str, str, float]]:
        """(key, [plant.initial] role, value) of every initial value set (the speed when > 0)."""
        values = [("initial_speed_mps", "speed", self.initial_speed_mps if self.initial_speed_mps > 0.0 else None),
                  ("initial_y_m", "y", self.initial_y_m), ("initial_yaw_rad", "yaw", self.initial_yaw_rad)]
        return [(key, role, value) for key, role, value in values if value is not None]

    @property
    def front_m(self) -> float:
        """From the plant's pose point forward to the front bumper (m): ``cg_to_front_m`` or half the length."""
        return self.length_m / 2.0 if self.cg_to_front_m is None else self.cg_to_front_m

    def input_map(self, role: str) -> SignalMap | None:
        return next((m for m in self.inputs if m.role == role), None)

    def output_map(self, role: str) -> SignalMap | None:
        return next((m for m in self.outputs if m.role == role), None)


@dataclass(frozen=True)
class DriverConfig:
    """``[driver]``: the guidance model, as pedal positions once per ECU cycle.

    The models disregard the object on purpose (the paper's driver is "asleep at
    the wheel or distracted by a cell phone"); each key below says which models
    read it. Equations: :mod:`cosim.world.driver_models`.
    """

    model: str = setting("full_throttle", allowed=("full_throttle", "cruise", "scripted", "hold_speed", "reacting"),
                         doc="the driver model (see Driver models)")
    accel_pedal_pct: float = setting(100.0, unit="%", allowed=Range(0.0, 100.0),
                                     doc="full_throttle: the accelerator pedal, held whatever happens")
    set_speed_mps: float = setting(20.0, unit="m/s", allowed=Range(0.0, 80.0), doc="cruise, hold_speed: the speed held")
    gain_pct_per_mps: float = setting(20.0, unit="%/(m/s)", allowed=Range(0.0, 1000.0),
                                      doc="cruise, hold_speed: proportional gain on the speed error")
    integral_gain_pct_per_m: float = setting(10.0, unit="%/m", allowed=Range(0.0, 1000.0),
                                             doc="hold_speed: integral gain on the accumulated speed error")
    release_drop_mps: float = setting(0.0, unit="m/s", allowed=Range(0.0, 80.0),
                                      doc="hold_speed: release the accelerator for good once the speed is this "
                                          "far below the set speed (Euro NCAP robot: 5 km/h); 0 = never")
    reaction_time_min_s: float = setting(0.70, unit="s", allowed=Range(0.0, 10.0),
                                         doc="reacting: the shortest reaction time drawn (Green 2000: a fully "
                                             "expected signal, 0.70-0.75 s)")
    reaction_time_max_s: float = setting(1.5, unit="s", allowed=Range(0.0, 10.0),
                                         doc="reacting: the longest reaction time drawn (Green 2000: a surprise, "
                                             "about 1.5 s)")
    felt_decel_mps2: float = setting(1.5, unit="m/s^2", allowed=Range(0.1, 20.0),
                                     doc="reacting: a deceleration the driver feels as the car braking by itself "
                                         "while the accelerator is down (crd's choice: above any coast-down)")
    over: str = setting("time", allowed=("time", "position"),
                        doc="scripted: the breakpoints' abscissa, time (s) or position (m)")
    points: tuple[tuple[float, float, float], ...] = setting(
        (), kind=POINTS, doc="scripted: rows [at, accel_pct, brake_pct], linearly interpolated, held at the ends")
    steering: SteeringConfig | None = setting(None, doc="[driver.steering]: who turns the wheel; absent: every "
                                                        "model above holds it straight (the paper's driver)")


@dataclass(frozen=True)
class ObjectConfig:
    """``[object]`` or one of ``[[objects]]``: a body on or beside the path.

    Path coordinates: ``x`` along the path, in the coordinate of the plant's
    position output (the ego's front bumper is that output plus
    ``[plant] front_bumper_offset_m``; the builtin plant starts with its front
    bumper at x = 0, so there ``position_m`` is the initial gap); ``y`` across
    it, left positive. ``position_m`` is the object's REAR at t = 0; the object
    occupies ``[rear, rear + length_m]`` along the path and
    ``lateral_m ± width_m/2`` across it, and moves at ``speed_mps`` along it.
    Longitudinal profile: constant speed, or braking at ``brake_decel_mps2``
    (reached linearly within ``brake_ramp_s``) down to ``brake_to_speed_mps``,
    starting at ``brake_at_s`` or when the ego's gap first falls to
    ``brake_at_gap_m`` (0 decel = never brakes). Lateral motion: at
    ``lateral_speed_mps`` toward ``lateral_end_m``, starting at ``lateral_at_s``
    or at ``lateral_at_gap_m`` (cut-in, cut-out). Equations:
    :mod:`cosim.world.scene_motion`. The gap of the triggers is the ego's
    distance along its heading from its front bumper to the object's nearest
    point (in 1-D: ``rear - bumper``).

    In the plane: ``pose`` or ``road_pose`` place the box's centre with a
    heading, and the motion above runs along that heading (the lateral motion
    across it); ``trajectory`` or ``crossing`` move the box's centre along a
    path instead (the motion keys above are then not used). ``target_class``
    names a protocol target, whose box it takes unless ``length_m`` and
    ``width_m`` are given.
    """

    enabled: bool = setting(True, doc="false: no object (an empty road)")
    name: str = setting("object", doc="the object's name (reports, events)")
    position_m: float = setting(225.0, unit="m", allowed=Range(-1e5, 1e5),
                                doc="the object's rear at t = 0, along the path (see above)")
    speed_mps: float = setting(0.0, unit="m/s", allowed=Range(-80.0, 80.0), doc="speed along the path")
    length_m: float = setting(1.8, unit="m", allowed=Range(0.0, 50.0), doc="length along the path")
    width_m: float = setting(0.6, unit="m", allowed=Range(0.0, 10.0), doc="width across the path")
    lateral_m: float = setting(0.0, unit="m", allowed=Range(-20.0, 20.0),
                               doc="centre's offset across the path, left positive")
    brake_decel_mps2: float = setting(0.0, unit="m/s^2", allowed=Range(0.0, 15.0), doc="braking; 0 = never brakes")
    brake_ramp_s: float = setting(0.0, unit="s", allowed=Range(0.0, 10.0), doc="time to reach brake_decel_mps2")
    brake_to_speed_mps: float = setting(0.0, unit="m/s", allowed=Range(0.0, 80.0), doc="braking ends at this speed")
    brake_at_s: float | None = setting(None, unit="s", allowed=Range(0.0, 3600.0), doc="braking starts at this time")
    brake_at_gap_m: float | None = setting(None, unit="m", allowed=Range(0.0, 1e4),
                                           doc="... or once the ego's gap first falls to this")
    lateral_speed_mps: float = setting(0.0, unit="m/s", allowed=Range(0.0, 10.0), doc="lateral speed toward lateral_end_m")
    lateral_end_m: float | None = setting(None, unit="m", allowed=Range(-20.0, 20.0), doc="lateral motion ends here")
    lateral_at_s: float | None = setting(None, unit="s", allowed=Range(0.0, 3600.0), doc="lateral motion starts at this time")
    lateral_at_gap_m: float | None = setting(None, unit="m", allowed=Range(0.0, 1e4),
                                             doc="... or once the ego's gap first falls to this")
    target_class: str | None = setting(None, allowed=tuple(TARGET_CLASSES),
                                       doc="a protocol target (cosim/world/targets.py): its box is length_m x width_m "
                                           "unless given, and the radar reports its size class")
    pose: PoseConfig | None = setting(None, doc="planar: [objects.pose] places the box's centre instead of "
                                                "position_m and lateral_m; the motion above runs along its heading")
    road_pose: RoadPoseConfig | None = setting(None, doc="planar: [objects.road_pose], the same in road coordinates")
    trajectory: TrajectoryConfig | None = setting(None, doc="planar: [objects.trajectory] moves it instead")
    crossing: CrossingConfig | None = setting(None, doc="planar: [objects.crossing] moves it instead")

    @property
    def planar(self) -> bool:
        """Placed or moved in the plane (any of the planar tables, or a protocol target class)."""
        return any(v is not None for v in (self.target_class, self.pose, self.road_pose, self.trajectory,
                                             self.crossing))


@dataclass(frozen=True)
class RadarConfig:
    """``[radar]``: range (front bumper → object rear) and range rate every 50 ms.

    Noise is zero-mean Gaussian from a generator seeded by ``[scenario] seed``;
    beyond ``max_range_m``, outside the field of view or on a dropout the track
    reports ``ObjectValid = 0``.
    """

    latency_s: float = setting(0.0, unit="s", allowed=Range(0.0, 1.0),
                               doc="measurement-to-bus latency, rounded to whole ECU cycles")
    range_noise_std_m: float = setting(0.0, unit="m", allowed=Range(0.0, 10.0), doc="standard deviation of range noise")
    range_rate_noise_std_mps: float = setting(0.0, unit="m/s", allowed=Range(0.0, 10.0),
                                              doc="standard deviation of range-rate noise")
    max_range_m: float = setting(200.0, unit="m", allowed=Range(1.0, 250.0), doc="objects beyond are not reported")
    dropout_probability: float = setting(0.0, allowed=Range(0.0, 1.0), doc="probability per update of no track")
    field_of_view_deg: float = setting(
        90.0, unit="deg", allowed=Range(1.0, 180.0),
        doc="full horizontal field of view; an object whose nearest rear corner is outside ±fov/2 of the "
            "bore sight is not seen (default ±45°: the near-range beam of a mid-range automotive radar)")
    front_corner: bool = setting(
        False, doc="planar scenes: the front corner radars are fitted too (crossing traffic ahead and to the side, "
                   "cosim.world.corner_radar): their tracks join the forward radar's in RadarTrack0..7, one list "
                   "most urgent first, with this table's latency, noise and dropouts")
    corner: bool = setting(
        False, doc="planar scenes: the rear corner radars are fitted too (blind-spot and lane-change sensors, "
                   "cosim.world.corner_radar): cars beside and behind, sent as CornerTrack0..3 with this table's "
                   "latency, noise and dropouts; false: those frames are not on the bus")


@dataclass(frozen=True)
class GatewayConfig:
    """``[gateway]``: the brake/powertrain ECU that applies ``SafetyOverride``."""

    brake_full_decel_mps2: float = setting(
        12.0, unit="m/s^2", allowed=Range(1.0, 30.0),
        doc="maps the ECU's deceleration request to a brake command: brake = min(1, request / this); "
            "default: the builtin plant's max_brake_force / mass = 18000 N / 1500 kg")
    override_timeout_s: float = setting(
        timeout_s("SafetyOverride"), unit="s", allowed=Range(ECU_CYCLE_S, 1.0),
        doc="silence (or an invalid E2E score) longer than this falls back to the driver's commands alone")


#: events ``[checks] expect_events`` may name: the faults that otherwise make a run exit 4
#: (``cosim.results.events.FAULT_EVENTS``)
EXPECTABLE_EVENTS = ("ecu_lost", "second_ecu", "auth_failure", "ecu_security_fault")


@dataclass(frozen=True)
class ChecksConfig:
    """``[checks]``: expectations on the run's metrics; unset = not checked."""

    no_collision: bool | None = setting(None, doc="the run must (true) or must not (false) end without contact")
    min_gap_m: float | None = setting(None, unit="m", allowed=Range(-1e5, 1e5), doc="the closest gap must stay above")
    max_impact_speed_mps: float | None = setting(None, unit="m/s", allowed=Range(0.0, 200.0),
                                                 doc="highest allowed relative impact speed")
    min_contingency_invocations: int | None = setting(None, allowed=Range(0, 10**6), doc="at least this many contingencies")
    max_contingency_invocations: int | None = setting(None, allowed=Range(0, 10**6), doc="at most this many contingencies")
    expect_events: tuple[str, ...] = setting(
        (), kind=event_names(EXPECTABLE_EVENTS),
        doc="fault events this scenario provokes on purpose (e.g. [\"ecu_lost\"]): each must occur (else the "
            "check fails, exit 3), and does not make the run exit 4")


@dataclass(frozen=True)
class EndConfig:
    """``[end]``: conditions that end the run early (contact and ``duration_s`` always do)."""

    standstill: bool = setting(False, doc="end once the ego's speed falls to standstill_speed_mps after having "
                                          "been above it")
    matched_speed: bool = setting(False, doc="end once the ego's speed falls to that of the nearest object ahead "
                                             "in its path after having been matched_speed_margin_mps above it "
                                             "(Euro NCAP's end of a longitudinal test)")
    standstill_speed_mps: float = setting(0.01, unit="m/s", allowed=Range(0.0, 5.0), doc="see standstill")
    matched_speed_margin_mps: float = setting(0.5, unit="m/s", allowed=Range(0.0, 10.0), doc="see matched_speed")


@dataclass(frozen=True)
class Scenario:
    """A whole scenario file (``objects``: the ``[[objects]]`` array; then ``object`` is disabled)."""

    scenario: ScenarioSection = setting(ScenarioSection(), doc="name, duration, step, seed, start time")
    plant: PlantConfig = setting(PlantConfig(), doc="the vehicle FMU")
    driver: DriverConfig = setting(DriverConfig(), doc="the driver model")
    object: ObjectConfig = setting(ObjectConfig(), doc="one object (or [[objects]], not both)")
    radar: RadarConfig = setting(RadarConfig(), doc="the radar model")
    gateway: GatewayConfig = setting(GatewayConfig(), doc="the brake/powertrain ECU")
    ecu: EcuConfig = setting(EcuConfig(), doc="the collision-avoidance ECU: every EcuConfig key")
    checks: ChecksConfig = setting(ChecksConfig(), doc="expectations on the run")
    objects: tuple[ObjectConfig, ...] = setting((), doc="several objects, each an [object] table")
    end: EndConfig = setting(EndConfig(), doc="early end conditions")
    road: RoadConfig | None = setting(None, doc="planar: the road (absent: none)")

    @property
    def planar(self) -> bool:
        """A scenario of the plane: a road, a steering driver, an initial pose or a planar object.

        It gets the builtin plant's planar maps, a ``scene.json`` and the pose columns; every other
        scenario runs, resolves and writes exactly as the 1-D world did (the world is the same).
        """
        return (self.road is not None or self.driver.steering is not None or self.plant.initial_y_m is not None
                or self.plant.initial_yaw_rad is not None or any(o.planar for o in self.scene_objects()))

    @property
    def equipment(self) -> str:
        """The ECU's equipment in this scene (:mod:`ecu.equipment`): ``longitudinal`` in the 1-D world;
        ``planar`` (the ESC and the 2-D radar) in the plane, ``planar_steering`` when its plant also takes the
        ECU's ``steer_request``, each with ``_corner`` when ``[radar] corner`` fits the rear corner radars. It
        decides which frames the run's bus carries (``EcuConfig.equipment``)."""
        return equipment_for(self.planar, any(m.role == "steer_request" for m in self.plant.inputs),
                             self.radar.corner).name

    def scene_objects(self) -> tuple[ObjectConfig, ...]:
        """Every enabled object: ``[[objects]]`` if given, else the single ``[object]``."""
        objs = self.objects or (self.object,)
        return tuple(o for o in objs if o.enabled)
