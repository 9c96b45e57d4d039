"""The topics of a run's MCAP file, each a stream of ``(log time (ns), CDR bytes)`` built from the run's files.

=========================== ================================== ==================================
topic                       type                               one message per
=========================== ================================== ==================================
``/can/frames``             ``can_msgs/msg/Frame``             frame of ``can.blf``
``/can/decoded/<Message>``  ``crd_can_msgs/msg/<Message>``     frame of that DBC message
``/run/sample``             ``crd_msgs/msg/RunSample``         row of ``timeseries.csv``
``/ego/odometry``           ``nav_msgs/msg/Odometry``          row
``/tf``                     ``tf2_msgs/msg/TFMessage``         row
``/scene/markers``          ``visualization_msgs/msg/MarkerArray`` change of the scene (first row,
                                                               then a new mode or stopping distance)
``/run/events``             ``rcl_interfaces/msg/Log``         event of ``events.json``
=========================== ================================== ==================================

The ECU's mode and limits are plottable on ``/can/decoded/SafetyOverride`` (``mode``,
``throttle_limit`` in %, ``brake_decel_request`` in m/s²) and ``/can/decoded/EcuStatus``
(``stopping_distance``, ``proximity``), its mode's name on ``/run/sample.ecu_mode``.
A decoded topic holds what each frame of a contract message says by the DBC (cantools'
decode), checked by nothing: a forged or corrupted frame the ECU rejected is decoded too.
The SecOC authenticator frames (freshness and MAC), and any frame the DBC cannot decode
(unknown ID, wrong length), are on ``/can/frames`` only; the latter are counted.

Times: the scenario's ``start_time`` plus the simulated time, in whole microseconds
(:func:`log_time_ns`): no wall clock.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from datetime import datetime, timezone
from typing import Any, Callable, Iterator, Sequence

import can
import numpy as np

from .mcap_scene import EgoState, SceneMessages, scene_changes, stopping_distances
from .mcap_schemas import CAN_FRAME, RUN_SAMPLE, Schemas, dbc_type, field_name, signal_type
from .run_record import TIMESERIES_COLUMNS, RunEvent, RunRecord

_EPOCH = datetime(1970, 1, 1, tzinfo=timezone.utc)
_LOG = "rcl_interfaces/msg/Log"
#: event kind -> rcl_interfaces/msg/Log level (others INFO)
EVENT_LEVELS = {"collision": "ERROR", "ecu_lost": "ERROR", "second_ecu": "ERROR", "ecu_security_fault": "ERROR",
                "auth_failure": "WARN", "override_timeout": "WARN", "warning": "WARN", "interrupted": "WARN"}
#: the stopping path's length: this signal of this message
STOPPING = ("EcuStatus", "StoppingDistance")


def epoch_ns(start_time: str) -> int:
    """An ISO 8601 time with its UTC offset (``[scenario] start_time``) in ns since 1970, exactly."""
    delta = datetime.fromisoformat(start_time) - _EPOCH
    return (delta.days * 86_400 + delta.seconds) * 1_000_000_000 + delta.microseconds * 1000


def log_time_ns(start_ns: int, t_s: float) -> int:
    """``start_ns`` plus ``t_s`` seconds of simulated time, rounded to a whole microsecond."""
    return start_ns + round(t_s * 1_000_000) * 1000


@dataclass(frozen=True)
class Topic:
    """One channel: its name, message type and messages ``(log time (ns), CDR bytes)`` in time order."""

    name: str
    typename: str
    count: int
    messages: Callable[[], Iterator[tuple[int, bytes]]]


@dataclass
class RunFiles:
    """What a topic is built from: the run's record, its CAN frames and start time, and its scenario."""

    record: RunRecord
    frames: list[can.Message]
    start_ns: int
    scenario: Any
    undecoded: int = 0  # frames of no message of the DBC, or that it cannot decode
    #: frame ID -> (log time (ns), bus name, signals) of each frame the DBC decodes
    decoded: dict[int, list[tuple[int, str, dict]]] = field(default_factory=dict)

    def frame_ns(self, msg: can.Message) -> int:
        return log_time_ns(self.start_ns, msg.timestamp - self.start_ns / 1e9)


def bus_name(msg: can.Message) -> str:
    """A frame's bus as a ROS frame id: ``can<n>`` for a log's channel number (``can0`` without one)."""
    channel = msg.channel if msg.channel is not None else 0
    return f"can{channel}" if isinstance(channel, int) else str(channel)


def decode_frames(run: RunFiles) -> None:
    """Decode each frame of a contract message (``can_dbc.LAYOUTS``; the SecOC authenticators'
    MACs stay raw) by the DBC into ``run.decoded`` (by frame ID, in log order); count the others."""
    from can_dbc import AUTHENTICATORS, DATABASE, LAYOUTS_BY_ID

    authenticators = set(AUTHENTICATORS.values())
    for msg in run.frames:
        if msg.arbitration_id in authenticators and not msg.is_extended_id:
            continue
        if msg.arbitration_id not in LAYOUTS_BY_ID or msg.is_extended_id or msg.is_error_frame:
            run.undecoded += 1
            continue
        try:
            signals = DATABASE.decode_message(msg.arbitration_id, bytes(msg.data), decode_choices=False)
        except Exception:  # noqa: BLE001 - cantools raises several kinds; the frame stays on /can/frames
            run.undecoded += 1
            continue
        run.decoded.setdefault(msg.arbitration_id, []).append((run.frame_ns(msg), bus_name(msg), signals))


def can_topics(schemas: Schemas, run: RunFiles) -> list[Topic]:
    """``/can/frames`` and one ``/can/decoded/<Message>`` per DBC message in the log (by frame ID)."""
    from can_dbc import DATABASE

    frame_type = schemas.type(CAN_FRAME)

    def frames() -> Iterator[tuple[int, bytes]]:
        for msg in run.frames:
            t = run.frame_ns(msg)
            data = np.frombuffer(bytes(msg.data[:8]).ljust(8, b"\0"), dtype=np.uint8)
            frame = frame_type(schemas.header(t, bus_name(msg)),
                               msg.arbitration_id, msg.is_remote_frame, msg.is_extended_id, msg.is_error_frame,
                               msg.dlc, data)
            yield t, schemas.serialize(frame, CAN_FRAME)

    topics = [Topic("/can/frames", CAN_FRAME, len(run.frames), frames)]
    for frame_id in sorted(run.decoded):
        message = DATABASE.get_message_by_frame_id(frame_id)
        topics.append(Topic(f"/can/decoded/{message.name}", dbc_type(message.name), len(run.decoded[frame_id]),
                            _decoded(schemas, message, run.decoded[frame_id])))
    return topics


def _decoded(schemas: Schemas, message: Any, entries: list) -> Callable[[], Iterator[tuple[int, bytes]]]:
    typename = dbc_type(message.name)
    cls = schemas.type(typename)
    fields = [(s.name, field_name(message.name, s.name), float if signal_type(s) == "float64" else int)
              for s in message.signals]

    def messages() -> Iterator[tuple[int, bytes]]:
        for t, bus, signals in entries:
            values = {f: kind(signals[name]) for name, f, kind in fields}
            decoded = cls(schemas.header(t, bus), **values)
            yield t, schemas.serialize(decoded, typename)

    return messages


def _pose_index(columns: tuple[str, ...], column: str) -> int | None:
    """Where a planar run's pose column (``y_m``, ``yaw_rad``) stands; None in a 1-D run's time series."""
    return columns.index(column) if column in columns else None


def ego_states(run: RunFiles) -> list[EgoState]:
    """Each row of the time series as an :class:`EgoState`, with the last stopping distance at or before it."""
    from can_dbc import DATABASE

    rows = run.record.rows
    times = [log_time_ns(run.start_ns, row[0]) for row in rows]
    status_id = DATABASE.get_message_by_name(STOPPING[0]).frame_id
    status = [(t, float(signals[STOPPING[1]])) for t, _, signals in run.decoded.get(status_id, [])]
    x, v, mode = (TIMESERIES_COLUMNS.index(c) for c in ("position_m", "speed_mps", "ecu_mode"))
    y, yaw = (_pose_index(run.record.columns, c) for c in ("y_m", "yaw_rad"))
    return [EgoState(t, row[0], row[x], 0.0 if y is None else row[y], 0.0 if yaw is None else row[yaw], row[v],
                     row[mode], d) for t, row, d in zip(times, rows, stopping_distances(times, status))]


def world_topics(schemas: Schemas, run: RunFiles) -> list[Topic]:
    """``/run/sample``, ``/ego/odometry``, ``/tf`` and ``/scene/markers``: one message per row each."""
    egos = ego_states(run)
    scene = SceneMessages(schemas, run.scenario)
    sample_type = schemas.type(RUN_SAMPLE)

    def samples() -> Iterator[tuple[int, bytes]]:
        for ego, row in zip(egos, run.record.rows):
            t = ego.t_ns
            values = dict(zip(TIMESERIES_COLUMNS, row))
            sample = sample_type(schemas.header(t, ""), **values)
            yield t, schemas.serialize(sample, RUN_SAMPLE)

    def each(rows: Sequence[EgoState], build: Callable[[EgoState], bytes]) -> Callable[[], Iterator[tuple[int, bytes]]]:
        return lambda: ((ego.t_ns, build(ego)) for ego in rows)

    n, changes = len(egos), scene_changes(egos)
    return [Topic("/run/sample", RUN_SAMPLE, n, samples),
            Topic("/ego/odometry", "nav_msgs/msg/Odometry", n, each(egos, scene.odometry)),
            Topic("/tf", "tf2_msgs/msg/TFMessage", n, each(egos, scene.transform)),
            Topic("/scene/markers", "visualization_msgs/msg/MarkerArray", len(changes), each(changes, scene.markers))]


def event_topic(schemas: Schemas, run: RunFiles) -> Topic:
    """``/run/events``: each event of ``events.json`` as a log line (Foxglove's Log panel, ``rqt_console``)."""
    cls = schemas.type(_LOG)
    events: Sequence[RunEvent] = sorted(run.record.events, key=lambda e: e.t_s)

    def messages() -> Iterator[tuple[int, bytes]]:
        for e in events:
            t = log_time_ns(run.start_ns, e.t_s if math.isfinite(e.t_s) else 0.0)
            level = getattr(cls, EVENT_LEVELS.get(e.kind, "INFO"))
            line = cls(schemas.stamp(t), level, "crd", f"{e.kind}: {e.detail}", "", "", 0)
            yield t, schemas.serialize(line, _LOG)

    return Topic("/run/events", _LOG, len(events), messages)
