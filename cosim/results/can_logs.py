"""A run's CAN frames as measurement files: BLF, ASC, TRC, candump ``.log``, CSV and MF4.

Every file starts at the scenario's ``[scenario] start_time`` (a fixed,
documented date by default, so the files are the same from run to run) and
stamps each frame with that start time plus its simulation time:

* python-can's writers (chosen by suffix; BLF given the frames in bulk, its
  containers at zlib level 1: :class:`FrameBlfWriter`) get absolute time stamps, so the BLF
  header's start time, the TRC ``$STARTTIME`` and the candump/CSV stamps are
  the run's start; the BLF offsets and the ASC times are the simulation time.
  The ASC ``date``/``Begin Triggerblock`` lines are the start time in its own
  UTC offset (python-can writes the wall clock of the moment it opened the
  file there);
* MF4 (ASAM MDF 4.10) is written with asammdf, an optional extra
  (``pip install 'crd[mdf]'``), in the ASAM bus-logging layout (one
  ``CAN_DataFrame`` channel group from a CAN bus source) that asammdf's
  ``extract_bus_logging`` decodes with the DBC. Its time axis is the
  simulation time (starting at 0) and its header's start time is the run's.

:func:`check_can_logs` rejects an unknown suffix or a missing extra before a
run starts, so a long run never ends in an error about its log file.
"""

from __future__ import annotations

import importlib.util
from datetime import datetime
from operator import itemgetter
from pathlib import Path, PurePath
from typing import Iterable, Sequence

import can
import numpy as np

from ..errors import ConfigError
from .run_record import LoggedFrame, RunRecord

#: suffix -> what writes it (python-can chooses its writer by the same suffix)
LOG_FORMATS = {
    ".blf": "Vector BLF (python-can)",
    ".asc": "Vector ASC (python-can)",
    ".trc": "PEAK TRC (python-can)",
    ".log": "candump log (python-can)",
    ".csv": "CSV (python-can)",
    ".mf4": "ASAM MDF 4.10 bus logging (asammdf, extra crd[mdf])",
}
DEFAULT_CAN_LOG = "can.blf"


def check_can_logs(names: Iterable[str]) -> tuple[str, ...]:
    """The default log plus ``names``, each checked; raises :class:`ConfigError` naming the option."""
    logs = [DEFAULT_CAN_LOG]
    names = (names,) if isinstance(names, str) else names  # one name, not its characters
    for name in names:
        suffix = PurePath(name).suffix.lower()
        if PurePath(name).name != name or not PurePath(name).stem:
            raise ConfigError(f"--can-log: expected a file name (written in each strategy's directory), got {name!r}")
        if suffix not in LOG_FORMATS:
            raise ConfigError(f"--can-log {name}: expected a suffix in {sorted(LOG_FORMATS)}, got {suffix or 'none'!r}")
        if suffix == ".mf4" and importlib.util.find_spec("asammdf") is None:
            raise ConfigError(f"--can-log {name}: MF4 needs asammdf, which is not installed;"
                              " install the extra: pip install 'crd[mdf]'")
        if name not in logs:
            logs.append(name)
    return tuple(logs)


class _DatedASCWriter(can.ASCWriter):
    """python-can's ASC writer with the run's start date in its header instead of the wall clock."""

    def __init__(self, path: Path, start: datetime) -> None:
        self._start = start  # set first: the base class writes the header in __init__
        super().__init__(str(path))

    def _format_header_datetime(self, dt: datetime) -> str:  # noqa: ARG002 - always the run's start
        return super()._format_header_datetime(self._start)


def _messages(record: RunRecord, start_s: float) -> Iterable[can.Message]:
    for f in record.frames:
        yield can.Message(timestamp=start_s + f.t_s, arbitration_id=f.arbitration_id, data=f.data,
                          is_extended_id=False, channel=0)


#: one CAN_MESSAGE object of a BLF file as python-can's ``BLFWriter`` writes it: its object header
#: (``<4sHHLL``), the V1 header (``<LHHQ``, time in ns) and the message (``<HBBL8s``), 48 bytes
_BLF_OBJECT = np.dtype([("signature", "S4"), ("header_size", "<u2"), ("header_version", "<u2"),
                        ("object_size", "<u4"), ("object_type", "<u4"), ("flags", "<u4"), ("client_index", "<u2"),
                        ("object_version", "<u2"), ("time_ns", "<u8"), ("channel", "<u2"), ("message_flags", "u1"),
                        ("dlc", "u1"), ("arbitration_id", "<u4"), ("data", "S8")])
_BLF_CONSTANTS = {"signature": b"LOBJ", "header_size": 32, "header_version": 1, "object_size": _BLF_OBJECT.itemsize,
                  "object_type": 1, "flags": 2, "client_index": 0, "object_version": 0, "channel": 1,
                  "message_flags": 0, "dlc": 8}  # CAN_MESSAGE, TIME_ONE_NANS, channel 0 + 1, received, DLC 8


#: a logged frame's fields (:class:`LoggedFrame`: t_s, arbitration_id, data)
_T_S, _ID, _DATA = itemgetter(0), itemgetter(1), itemgetter(2)

#: zlib level of the BLF containers: 1 (Z_BEST_SPEED) compresses a run's frames about four times
#: faster than python-can's default 6 (5.8 instead of 23.5 ms for the paper run's 26,000 frames,
#: timeit) into a file 7.5 % larger (273 instead of 254 kB); every reader inflates either the same
#: (BLF stores the method, deflate, not the level), so the frames read back are identical
BLF_COMPRESSION_LEVEL = 1


class FrameBlfWriter(can.BLFWriter):
    """python-can's BLF writer, given a run's frames in bulk (:meth:`write_frames`), containers at zlib level 1.

    ``on_message_received`` costs about 10 µs a frame (a ``can.Message`` built for it, then
    three ``struct.pack`` calls and list appends), a third of a run's time. Here a batch of
    frames becomes one array of BLF objects (numpy, ``_BLF_OBJECT``: a classic frame's data
    padded to 8 bytes, its DLC its length, as python-can packs them), with the time stamps
    computed exactly as python-can computes them; python-can still writes the containers,
    the header and its statistics. The file is byte for byte what ``on_message_received``
    writes at the same level (tested, ``tests/cosim/test_log_cost.py``: it relies on the
    writer's ``_buffer``/``_buffer_size``, python-can 4.x, which that test guards).
    """

    def __init__(self, file, compression_level: int = BLF_COMPRESSION_LEVEL, **kwargs) -> None:
        super().__init__(file, compression_level=compression_level, **kwargs)

    def write_frames(self, frames: Sequence[LoggedFrame], start_s: float) -> None:
        """Log ``frames`` (classic CAN, 11-bit, received, time stamp ``start_s + t_s``)."""
        self.add_objects(self.objects(frames, start_s))

    def objects(self, frames: Sequence[LoggedFrame], start_s: float) -> bytes:
        """``frames`` as BLF objects, counted, the header's time span moved (as ``_add_object`` does); not yet logged.

        Each field is read with ``map(itemgetter(i), frames)`` into numpy, never ``zip(*frames)``: that
        made an iterator per frame, tracked by the garbage collector, and the collections they set
        off walked the run's young frames (in a run, 5 of the 5.5 ms this took per simulated second).
        """
        n = len(frames)
        if not n:
            return b""
        t_s = np.fromiter(map(_T_S, frames), dtype=np.float64, count=n)
        stamps = start_s + t_s  # the same IEEE additions as start_s + f.t_s
        if self.start_timestamp is None:  # as BLFWriter._add_object: the first stamp, to the millisecond
            self.start_timestamp = int(float(stamps[0]) * 1000) / 1000
        self.stop_timestamp = float(stamps[-1])
        self.object_count += n
        objects = np.empty(n, dtype=_BLF_OBJECT)
        for name, value in _BLF_CONSTANTS.items():
            objects[name] = value
        objects["time_ns"] = np.maximum(((stamps - self.start_timestamp) * 1e9).astype(np.int64), 0)
        objects["arbitration_id"] = np.fromiter(map(_ID, frames), dtype=np.int64, count=n)
        payloads = list(map(_DATA, frames))
        if set(map(len, payloads)) == {8}:  # every frame of the contract
            objects["data"] = np.frombuffer(b"".join(payloads), dtype="S8")
        else:  # python-can's "8s" pads and cuts; the DLC stays the frame's length
            objects["dlc"] = [len(data) for data in payloads]
            objects["data"] = np.frombuffer(b"".join(bytes(d)[:8].ljust(8, b"\0") for d in payloads), dtype="S8")
        return objects.tobytes()

    def add_objects(self, block: bytes) -> None:
        """Log BLF objects made by :meth:`objects`; a container is written at each ``max_container_size``."""
        self._buffer.append(block)
        self._buffer_size += len(block)
        while self._buffer_size >= self.max_container_size:  # python-can flushes at each crossing
            self._flush()


def open_python_can_writer(path: Path, start: datetime) -> can.io.generic.MessageWriter:
    """python-can's writer for ``path``'s suffix (ASC dated with ``start``; BLF in bulk, zlib level 1:
    :class:`FrameBlfWriter`)."""
    suffix = path.suffix.lower()
    if suffix == ".asc":
        return _DatedASCWriter(path, start)
    return FrameBlfWriter(str(path)) if suffix == ".blf" else can.Logger(str(path))


def streamed(name: str) -> bool:
    """Whether a log is written while the run goes (python-can's writers) or at its end (MF4)."""
    return PurePath(name).suffix.lower() != ".mf4"


def _write_python_can(path: Path, record: RunRecord, start: datetime) -> None:
    start_s = start.timestamp()
    writer = open_python_can_writer(path, start)
    with writer:
        if isinstance(writer, FrameBlfWriter):
            writer.write_frames(record.frames, start_s)
            return
        for msg in _messages(record, start_s):
            writer.on_message_received(msg)


def _write_mf4(path: Path, record: RunRecord, start: datetime) -> None:
    """All frames as one ASAM bus-logging ``CAN_DataFrame`` group on bus channel 1."""
    import numpy as np
    from asammdf import MDF, Signal, Source

    n = len(record.frames)
    layout = np.dtype([("CAN_DataFrame.BusChannel", "<u1"), ("CAN_DataFrame.ID", "<u4"),
                       ("CAN_DataFrame.IDE", "<u1"), ("CAN_DataFrame.DLC", "<u1"),
                       ("CAN_DataFrame.DataLength", "<u1"), ("CAN_DataFrame.DataBytes", "(8,)u1"),
                       ("CAN_DataFrame.Dir", "<u1")])
    samples = np.zeros(n, dtype=layout)
    samples["CAN_DataFrame.BusChannel"] = 1
    samples["CAN_DataFrame.ID"] = [f.arbitration_id for f in record.frames]
    samples["CAN_DataFrame.DLC"] = samples["CAN_DataFrame.DataLength"] = [len(f.data) for f in record.frames]
    payload = b"".join(bytes(f.data).ljust(8, b"\0") for f in record.frames)
    samples["CAN_DataFrame.DataBytes"] = np.frombuffer(payload, dtype=np.uint8).reshape(n, 8)
    source = Source("CAN1", "crd co-simulation", "classic CAN, 11-bit IDs", Source.SOURCE_BUS, Source.BUS_TYPE_CAN)
    times_s = np.array([f.t_s for f in record.frames], dtype=float)
    mdf = MDF(version="4.10")
    try:
        mdf.header.start_time = start
        mdf.append(Signal(name="CAN_DataFrame", samples=samples, timestamps=times_s, source=source),
                   acq_name="CAN1", acq_source=source, comment="crd run, strategy " + record.strategy)
        written = Path(mdf.save(path, overwrite=True))
    finally:
        mdf.close()
    if written != path:  # asammdf writes the suffix in lower case
        written.replace(path)


def write_can_logs(run_dir: Path, record: RunRecord, names: Sequence[str], start: datetime) -> list[Path]:
    """Write ``record``'s frames to each file in ``names`` (checked by :func:`check_can_logs`)."""
    paths = []
    for name in names:
        path = run_dir / name
        (_write_mf4 if path.suffix.lower() == ".mf4" else _write_python_can)(path, record, start)
        paths.append(path)
    return paths
