"""Issue 25, item 5: a run's logs written a simulated second at a time as it runs (:mod:`cosim.results.stream`).

A write that fails (a full disk) stops the run with a one-line error naming it and keeps what was
written; and the streamed files are, batch for batch, python-can's and ``csv``'s own bytes.
"""

from __future__ import annotations

import errno
import json
from datetime import datetime, timezone

import can
import pytest

from cosim.cli.main import main as crd
from cosim.results.can_logs import FrameBlfWriter
from cosim.results.run_record import RunMetrics, RunRecord
from cosim.results.stream import LogWriteError, RunStream
from cosim.results.writer import write_timeseries
from tests.cosim.test_log_cost import START_S, _frames, _per_message

START = datetime.fromtimestamp(START_S, tz=timezone.utc)


def _row(i: int) -> tuple:
    return (i * 0.01, 0.5 * i, 20.0 - i * 1e-3, -1.5, 1.0, 0.0, "STANDBY", 40.0 - 0.3 * i, 100.0, 0.0)


def _stream_in_batches(run_dir, batches: int = 5) -> RunRecord:
    """A record grown by ``batches`` seconds of rows and frames, flushed after each, then closed."""
    record = RunRecord("none", RunMetrics("none"))
    frames = _frames(650 * batches, t0_s=0.0137)
    stream = RunStream(run_dir, ["can.blf", "x.asc"], START)
    for b in range(batches):
        record.rows.extend(_row(i) for i in range(100 * b, 100 * (b + 1)))
        record.frames.extend(frames[650 * b:650 * (b + 1)])
        stream.flush(record)
    stream.close(record)
    return record


def test_the_streamed_files_are_python_cans_and_csvs_bytes(tmp_path):
    record = _stream_in_batches(tmp_path / "run")
    batches = [record.frames[i:i + 650] for i in range(0, len(record.frames), 650)]
    assert (tmp_path / "run" / "can.blf").read_bytes() == _per_message(tmp_path / "expected.blf", batches)
    write_timeseries(tmp_path / "expected.csv", record)
    assert (tmp_path / "run" / "timeseries.csv").read_bytes() == (tmp_path / "expected.csv").read_bytes()
    asc = list(can.ASCReader(str(tmp_path / "run" / "x.asc")))
    assert [(m.arbitration_id, bytes(m.data)) for m in asc] == [(f.arbitration_id, f.data) for f in record.frames]


def _disk_full(*_args) -> None:
    raise OSError(errno.ENOSPC, "No space left on device")


def test_a_failed_write_is_raised_once_and_nothing_more_is_written(tmp_path, monkeypatch):
    record = RunRecord("none", RunMetrics("none"), rows=[_row(0)], frames=_frames(30))
    stream = RunStream(tmp_path / "run", ["can.blf"], START)
    monkeypatch.setattr(FrameBlfWriter, "add_objects", _disk_full)
    with pytest.raises(LogWriteError, match=rf"^{tmp_path / 'run'}: writing the logs failed: \[Errno 28\] No space"):
        stream.flush(record)
    record.rows.append(_row(1))
    stream.flush(record)  # reported once: the run's way out does not raise it again, and writes nothing more
    stream.close(record)
    assert (tmp_path / "run" / "timeseries.csv").read_text().count("\n") == 2  # the header and the first row


def test_a_write_that_fails_in_the_last_batch_is_raised_by_close_and_the_files_are_closed(tmp_path, monkeypatch):
    monkeypatch.setattr(FrameBlfWriter, "add_objects", _disk_full)
    record = RunRecord("none", RunMetrics("none"), rows=[_row(0)], frames=_frames(30))
    stream = RunStream(tmp_path / "run", ["can.blf"], START)
    with pytest.raises(LogWriteError, match="No space left on device"):
        stream.close(record)
    assert stream._csv_file.closed
    assert (tmp_path / "run" / "timeseries.csv").read_text().count("\n") == 2  # written before the BLF failed
    stream.close(record)  # idempotent


SCENARIO = '[scenario]\nduration_s = 6.0\n[object]\nposition_m = 80.0\n[ecu]\nstrategy = "none"\n'


def test_a_disk_that_fills_mid_run_stops_it_with_one_line_and_keeps_the_logs_so_far(tmp_path, monkeypatch, capsys):
    """The BLF's third container fails: the run stops on the error, metrics.json says so, and the time series
    and the BLF (closed, readable) keep the seconds written before."""
    calls = []
    real = FrameBlfWriter.add_objects

    def fill_at_third(self, block: bytes) -> None:
        calls.append(len(block))
        if len(calls) == 3:
            _disk_full()
        real(self, block)

    monkeypatch.setattr(FrameBlfWriter, "add_objects", fill_at_third)
    (tmp_path / "s.toml").write_text(SCENARIO)
    out = tmp_path / "out"
    assert crd(["run", str(tmp_path / "s.toml"), "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == f"error: {out / 'none'}: writing the logs failed: [Errno 28] No space left on device"
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["status"] == "error" and "No space left on device" in metrics["error"]
    frames = list(can.BLFReader(str(out / "none" / "can.blf")))
    rows = (out / "none" / "timeseries.csv").read_text().splitlines()[1:]
    assert float(rows[-1].split(",")[0]) >= 2.99 and len(rows) < 600  # whole seconds up to the failure, not the run
    assert frames and frames[-1].timestamp - START_S == pytest.approx(1.99, abs=0.011)  # the two seconds before it
