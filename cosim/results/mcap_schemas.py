"""The ROS 2 message types of crd's MCAP files, and their definitions as MCAP schemas.

Every channel is ROS 2 CDR with a ``ros2msg`` schema (the MCAP ``ros2`` profile), so that
``ros2 bag``, RViz (through ``ros2 bag play``), Foxglove and rosbags all read the file:

* the standard types (``nav_msgs/msg/Odometry``, ``tf2_msgs/msg/TFMessage``,
  ``visualization_msgs/msg/MarkerArray``, ``rcl_interfaces/msg/Log``) come from rosbags'
  type store of ROS 2 Jazzy (:data:`ROS_DISTRO`; Jazzy's ``Marker`` has the texture and
  mesh-file fields Humble's lacks, so a Humble subscriber cannot take them);
* ``can_msgs/msg/Frame`` is the frame type of ros-industrial's ``ros_canopen`` (ROS 2
  branch, ``can_msgs/msg/Frame.msg``), which ``ros2_socketcan`` publishes too;
* crd's own types are generated, so they cannot drift from their sources: one
  ``crd_can_msgs/msg/<Message>`` per contract message of the DBC (``can_dbc.LAYOUTS``: the
  E2E-protected ones, not the SecOC authenticators; a field per signal in DBC units, named
  in snake case without the message-name prefix of the E2E signals; integer
  signals as integers with their ``VAL_`` names as constants), and ``crd_msgs/msg/RunSample``
  with a field per ``timeseries.csv`` column.

A schema's text is the type's definition followed by each type it uses, separated by a
line of 80 ``=`` and a ``MSG: package/Type`` line: the layout rosbag2 writes, which
rosbags' :meth:`generate_msgdef` produces. crd's own definitions keep their comments
(units, the DBC's descriptions).
"""

from __future__ import annotations

import functools
import re
from dataclasses import dataclass
from typing import Any, Sequence

from rosbags.typesys import Stores, get_typestore, get_types_from_msg

from .run_record import TIMESERIES_COLUMNS

#: the ROS 2 distribution whose standard message definitions the files carry
ROS_DISTRO = Stores.ROS2_JAZZY
CAN_FRAME = "can_msgs/msg/Frame"
#: ros-industrial/ros_canopen, can_msgs/msg/Frame.msg (ROS 2 branch)
CAN_FRAME_MSG = """\
# A CAN frame (can_msgs of ros-industrial/ros_canopen, the type ros2_socketcan publishes).
std_msgs/Header header
uint32 id
bool is_rtr
bool is_extended
bool is_error
uint8 dlc
uint8[8] data
"""
RUN_SAMPLE = "crd_msgs/msg/RunSample"
CAN_PACKAGE = "crd_can_msgs"
#: column -> ROS field type (the rest are float64)
_SAMPLE_TYPES = {"ecu_mode": "string"}
_SEPARATOR = "=" * 80 + "\n"


def field_name(message: str, signal: str) -> str:
    """``SafetyOverride_Counter`` -> ``counter``, ``WheelSpeedFL`` -> ``wheel_speed_fl``, ``FaultE2E`` -> ``fault_e2e``."""
    name = signal.removeprefix(f"{message}_")
    return re.sub(r"(?<=[a-z])(?=[A-Z])|(?<=[A-Z])(?=[A-Z][a-z])", "_", name).lower()


def signal_type(signal: Any) -> str:
    """The ROS type of a cantools signal: an integer type when its physical value is its raw integer."""
    if signal.is_float or signal.scale != 1 or signal.offset != 0:
        return "float64"
    bits = next(b for b in (8, 16, 32, 64) if signal.length <= b)
    return f"{'int' if signal.is_signed else 'uint'}{bits}"


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _constant(field: str, name: str) -> str:
    return f"{field}_{re.sub(r'[^A-Za-z0-9]+', '_', str(name))}".upper()


def dbc_message_msg(message: Any) -> str:
    """The ``.msg`` text of one DBC message (a cantools message): a header and one field per signal."""
    lines = [f"# {message.name} (0x{message.frame_id:03X}) of the crd DBC, decoded (DBC units, not checked)."]
    if message.comment:
        lines.append(f"# {_one_line(message.comment)}")
    lines.append("std_msgs/Header header")
    for signal in message.signals:
        field, kind = field_name(message.name, signal.name), signal_type(signal)
        for value, name in (signal.choices or {}).items():
            lines.append(f"{kind} {_constant(field, name)}={int(value)}")
        unit = f" [{signal.unit}]" if signal.unit else ""
        lines.append(f"{kind} {field}  # {signal.name}{unit}" + (f": {_one_line(signal.comment)}" if signal.comment else ""))
    return "\n".join(lines) + "\n"


def run_sample_msg(columns: Sequence[str] = TIMESERIES_COLUMNS) -> str:
    """The ``.msg`` text of one ``timeseries.csv`` row: a header and one field per column."""
    lines = ["# One row of crd's timeseries.csv (one ECU cycle): SI units, named by the column names.",
             "std_msgs/Header header"]
    lines += [f"{_SAMPLE_TYPES.get(c, 'float64')} {c}" for c in columns]
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class Schemas:
    """The type store (standard types and crd's) and crd's own definitions with their comments."""

    store: Any
    texts: dict[str, str]

    def definition(self, typename: str) -> str:
        """The MCAP schema text of ``typename``: its definition, then each type it uses."""
        generated, separator, used = self.store.generate_msgdef(typename, ros_version=2)[0].partition(_SEPARATOR)
        return self.texts.get(typename, generated) + separator + used

    def type(self, typename: str) -> type:
        """The message class rosbags builds for ``typename`` (fields by name)."""
        return self.store.types[typename]

    def stamp(self, t_ns: int) -> Any:
        """``builtin_interfaces/msg/Time`` of ``t_ns`` (ns since 1970)."""
        return self.store.types["builtin_interfaces/msg/Time"](t_ns // 1_000_000_000, t_ns % 1_000_000_000)

    def header(self, t_ns: int, frame_id: str) -> Any:
        """``std_msgs/msg/Header`` stamped ``t_ns`` in ``frame_id``."""
        return self.store.types["std_msgs/msg/Header"](self.stamp(t_ns), frame_id)

    def serialize(self, message: object, typename: str) -> bytes:
        """``message`` as little-endian ROS 2 CDR (with its 4-byte encapsulation header)."""
        return bytes(self.store.serialize_cdr(message, typename, little_endian=True))


def dbc_type(message_name: str) -> str:
    return f"{CAN_PACKAGE}/msg/{message_name}"


@functools.lru_cache(maxsize=4)
def crd_schemas(columns: tuple[str, ...] = TIMESERIES_COLUMNS) -> Schemas:
    """ROS 2 Jazzy's types with ``can_msgs/msg/Frame``, the DBC's messages and the run sample added."""
    from can_dbc import DATABASE, LAYOUTS

    texts = {CAN_FRAME: CAN_FRAME_MSG, RUN_SAMPLE: run_sample_msg(columns)}
    texts.update({dbc_type(name): dbc_message_msg(DATABASE.get_message_by_name(name)) for name in sorted(LAYOUTS)})
    store = get_typestore(ROS_DISTRO)
    types: dict = {}
    for name, text in texts.items():
        types.update(get_types_from_msg(text, name))
    store.register(types)
    return Schemas(store, texts)
