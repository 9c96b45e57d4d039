"""What one closed-loop run produces: its time series, frame log, events and metrics."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Mapping, NamedTuple

if TYPE_CHECKING:  # annotations only: the records must not import the world
    from ..scenarios.config import Scenario
    from ..world.ego import Ego
    from ..world.scene import Scene

TIMESERIES_COLUMNS = ("time_s", "position_m", "speed_mps", "accel_mps2", "throttle", "brake",
                      "ecu_mode", "gap_m", "accel_pedal_pct", "brake_pedal_pct")
#: what a planar run's rows add (docs/run-format.md): the ego's pose point and heading, the steering-wheel
#: angle the plant got, then per object (``obj<i>_``, 0-based, the order of the scenario's objects) its box's
#: centre and heading
EGO_POSE_COLUMNS = ("x_m", "y_m", "yaw_rad", "steering_wheel_angle_rad")
OBJECT_POSE_COLUMNS = ("x_m", "y_m", "yaw_rad")
#: then the ECU's stopping region as its last ``EcuRegionStatus`` reported it (NaN before the first; the
#: contingency as its DBC value, ``NOT_EVALUATED`` without planar tracks) and the steering overlay the EPS applied
REGION_COLUMNS = ("region_contingency", "region_proximity", "region_curvature_1pm", "region_clearance_m",
                  "region_stopping_m", "steer_overlay_rad")


def timeseries_columns(scenario: Scenario, n_objects: int | None = None) -> tuple[str, ...]:
    """The time series' columns of a run of ``scenario``: :data:`TIMESERIES_COLUMNS`, and the pose columns when
    it is planar (a 1-D scenario's file stays as it was); ``n_objects``: the scene's objects when it has more
    than the scenario declares (a fleet's other cars)."""
    if not scenario.planar:
        return TIMESERIES_COLUMNS
    n = len(scenario.scene_objects()) if n_objects is None else n_objects
    objects = [f"obj{i}_{c}" for i in range(n) for c in OBJECT_POSE_COLUMNS]
    return (*TIMESERIES_COLUMNS, *EGO_POSE_COLUMNS, *objects, *REGION_COLUMNS)


def pose_cells(ego: Ego, steering_rad: float, scene: Scene, t_s: float) -> tuple[float, ...]:
    """A planar row's pose cells at ``t_s`` (:data:`EGO_POSE_COLUMNS`, then each object's)."""
    cells = [ego.x_m, ego.y_m, ego.yaw_rad, steering_rad]
    for obj, st in zip(scene.objects, scene.states(t_s)):
        cells += (*obj.centre(st), st.yaw_rad)
    return tuple(cells)


class LoggedFrame(NamedTuple):
    """One bus frame with its simulation time stamp (s); a tuple, as the master logs every frame."""

    t_s: float
    arbitration_id: int
    data: bytes


@dataclass(frozen=True, slots=True)
class RunEvent:
    """Something that happened at ``t_s``; ``data``: fields ``events.json`` adds (a planar collision's contact)."""

    t_s: float
    kind: str
    detail: str
    data: Mapping[str, Any] | None = None


@dataclass
class RunMetrics:
    """The ``metrics.json`` entry of one run (SI units; ``None`` where not applicable)."""

    strategy: str
    collided: bool = False
    impact_speed_mps: float | None = None
    min_gap_m: float | None = None
    final_gap_m: float | None = None
    contingency_invocations: int = 0
    #: entries into the ECU's FAULT mode after start-up (issue 25: none on a clean run)
    fault_entries: int = 0
    max_speed_mps: float = 0.0
    sim_time_s: float = 0.0
    wall_time_s: float = 0.0
    #: why the run ended early: an ``[end]`` condition (``standstill``, ``matched_speed``), else None
    end_reason: str | None = None

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


@dataclass
class RunRecord:
    """Everything a run leaves behind; kept even when the run stops on an error."""

    strategy: str
    metrics: RunMetrics
    rows: list[tuple] = field(default_factory=list)  # ``columns``, one per ECU cycle
    columns: tuple[str, ...] = TIMESERIES_COLUMNS
    frames: list[LoggedFrame] = field(default_factory=list)
    events: list[RunEvent] = field(default_factory=list)
    error: str | None = None
    fmu_path: str = ""
    fmu_sha256: str = ""
    cycle_cost_s: dict[str, float] = field(default_factory=dict)  # filled when profiling
    timing: dict[str, float] = field(default_factory=dict)  # real time: the master's lag/jitter (s)
    ecu_report: str = ""  # what a spawned crd ecu printed (its run summary)
    ecu_join_wait_s: float = 0.0  # wall time spent waiting for an out-of-process ECU to join (in wall_time_s)
    interrupted: str | None = None  # the signal that ended the run early ("SIGINT", "SIGTERM")
    #: an ECU on a bus: the settings it announced and what is known of them (cosim.link.ecu_identity)
    ecu_settings: dict | None = None
    #: a planar run's collision (cosim.world.scene_contact.Hit.as_dict): metrics.json's "contact"
    contact: dict | None = None

    @property
    def status(self) -> str:
        """How the run ended: ``interrupted``, ``error``, ``collided`` or ``ok`` (ran its full duration)."""
        if self.interrupted:
            return "interrupted"
        if self.error:
            return "error"
        return "collided" if self.metrics.collided else "ok"

    def column(self, name: str) -> list:
        i = self.columns.index(name)
        return [row[i] for row in self.rows]
