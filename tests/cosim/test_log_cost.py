"""Issue 25, item 5: logging that costs little, with the same content.

The BLF is written in bulk (:class:`cosim.results.can_logs.FrameBlfWriter`, containers at zlib
level 1), the time series with one ``%`` per row (:func:`cosim.results.writer.timeseries_lines`).
The bulk writer must give exactly the bytes of python-can's ``on_message_received`` per frame
at the same level, and frames identical to it at python-can's default level 6 when read back;
the time series exactly ``csv.writer``'s bytes over :func:`~cosim.results.writer.timeseries_cells`.
(The speed: ``benchmarks/bench_logging.py``.)
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import can
import pytest

from can_dbc import CounterSequence, encode
from cosim.results.can_logs import BLF_COMPRESSION_LEVEL, FrameBlfWriter
from cosim.results.run_record import LoggedFrame
from cosim.results.writer import timeseries_cells, timeseries_lines

START_S = 1577836800.0  # the default [scenario] start_time, 2020-01-01 00:00 UTC


def _frames(n: int, t0_s: float = 0.0) -> list[LoggedFrame]:
    """``n`` frames of the contract, a few per 10 ms cycle, with awkward float times."""
    wheels, driver = CounterSequence(), CounterSequence()
    out = []
    for i in range(n):
        t_s = t0_s + (i // 3) * 0.01 + (1e-9 if i % 7 == 0 else 0.0)
        msg = (encode("WheelSpeeds", {f"WheelSpeed{w}": 0.05 * i % 400 for w in ("FL", "FR", "RL", "RR")},
                      wheels.next()) if i % 2 else
               encode("DriverInput", {"AccelPedal": 100.0, "BrakePedal": 0.0,
                                      "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0},
                      driver.next()))
        out.append(LoggedFrame(t_s, msg.arbitration_id, bytes(msg.data)))
    return out


def _per_message(path: Path, batches, max_container_size: int | None = None,
                 level: int = BLF_COMPRESSION_LEVEL) -> bytes:
    """python-can's own way: one can.Message per frame, a container closed after each batch."""
    writer = can.BLFWriter(str(path), compression_level=level,
                           **({"max_container_size": max_container_size} if max_container_size else {}))
    for batch in batches:
        for f in batch:
            writer.on_message_received(can.Message(timestamp=START_S + f.t_s, arbitration_id=f.arbitration_id,
                                                   data=f.data, is_extended_id=False, channel=0))
        writer._flush()
    writer.stop()
    return path.read_bytes()


def _batches() -> list[list[LoggedFrame]]:
    frames = _frames(3000, t0_s=0.0137)
    return [frames[i:i + 650] for i in range(0, len(frames), 650)]


@pytest.mark.parametrize("max_container_size", [None, 4096], ids=["one container per batch", "several"])
def test_the_bulk_blf_writer_writes_python_cans_bytes(tmp_path, max_container_size):
    batches = _batches()
    expected = _per_message(tmp_path / "a.blf", batches, max_container_size)
    writer = FrameBlfWriter(str(tmp_path / "b.blf"))
    if max_container_size:
        writer.max_container_size = max_container_size
    for batch in batches:
        writer.write_frames(batch, START_S)
        writer._flush()
    writer.stop()
    assert (tmp_path / "b.blf").read_bytes() == expected
    assert len(list(can.BLFReader(str(tmp_path / "b.blf")))) == 3000


def test_frames_that_are_not_8_bytes_are_padded_and_cut_as_python_can_does(tmp_path):
    batch = _frames(20) + [LoggedFrame(0.5, 0x123, b"\x01\x02\x03"), LoggedFrame(0.5, 0x7FF, b""),
                           LoggedFrame(0.51, 0x124, bytes(range(12)))]
    expected = _per_message(tmp_path / "a.blf", [batch])
    writer = FrameBlfWriter(str(tmp_path / "b.blf"))
    writer.write_frames(batch, START_S)
    writer._flush()
    writer.stop()
    assert (tmp_path / "b.blf").read_bytes() == expected


def _read(path: Path) -> list[tuple]:
    with can.BLFReader(str(path)) as reader:
        return [(m.timestamp, m.arbitration_id, m.is_extended_id, m.is_rx, m.dlc, bytes(m.data), m.channel)
                for m in reader]


def test_level_1_reads_back_the_frames_of_pythons_cans_default_level(tmp_path):
    """The level is invisible to a reader: the same frames and header statistics, a slightly larger file."""
    batches = _batches()
    _per_message(tmp_path / "default.blf", batches, level=-1)
    writer = FrameBlfWriter(str(tmp_path / "ours.blf"))
    for batch in batches:
        writer.write_frames(batch, START_S)
        writer._flush()
    writer.stop()
    assert _read(tmp_path / "ours.blf") == _read(tmp_path / "default.blf")
    with can.BLFReader(str(tmp_path / "ours.blf")) as ours, can.BLFReader(str(tmp_path / "default.blf")) as default:
        assert (ours.start_timestamp, ours.stop_timestamp, ours.object_count) == (
            default.start_timestamp, default.stop_timestamp, default.object_count)
    assert (tmp_path / "ours.blf").read_bytes() != (tmp_path / "default.blf").read_bytes()


def _csv(rows) -> str:
    text = io.StringIO(newline="")
    writer = csv.writer(text)
    for row in rows:
        writer.writerow(timeseries_cells(row))
    return text.getvalue()


ROW = (0.01, 1.25, 30.123456789, -3.5e-7, 1.0, 0.0, "TIGHTENING", math.inf, 100.0, 0.0)


@pytest.mark.parametrize("rows", [
    [ROW, tuple(x * 3.3 if isinstance(x, float) else x for x in ROW)],
    [ROW[:7] + (math.nan,) + ROW[8:]],
    [ROW[:8] + (100, 0)],  # integers (a driver model's 100): csv writes them as they are
    [ROW[:8] + (10_000_000, True)],  # where %.6g would not
    [ROW[:6] + ("A,B",) + ROW[7:]],  # a mode csv must quote
    [ROW[:6] + (1.5,) + ROW[7:]],  # a number where the mode goes
    [ROW[:1] + ("x",) + ROW[2:]],  # a word where a number goes
    [ROW[:7] + (None,) + ROW[8:]],
    [],
], ids=["floats", "nan", "ints", "large int and bool", "quoted mode", "float mode", "word", "None", "none"])
def test_the_time_series_lines_are_csvs_bytes(rows):
    assert timeseries_lines(rows) == _csv(rows)
