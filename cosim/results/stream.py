"""Results that survive: output paths checked before a run, files written while it runs.

* :func:`check_out_dir` runs before any simulation: ``--out`` and each
  strategy's directory must be (or become) writable directories; a path under
  a regular file, or in a directory that cannot be written, is a
  :class:`~cosim.errors.ConfigError` naming the path, at once instead of
  after the run.
* :class:`RunStream` writes one strategy's ``timeseries.csv`` and CAN logs
  (all but MF4, which asammdf writes at the end) as the run goes:
  :meth:`RunStream.flush` (called every 100 ECU cycles, i.e. every simulated
  second) appends the rows and frames recorded since the last
  call and hands them to the operating system, so a run killed at any moment
  (even SIGKILL) leaves its files complete up to the last simulated second. :meth:`close`
  writes the rest and closes the files (the BLF header gets its statistics).
  The rows and frames stay in the :class:`RunRecord` too (the metrics, plots
  and tests use them).

What it costs (issue 25; ``benchmarks/bench_logging.py``): :meth:`RunStream.flush` writes the new
rows and frames (slices of the record) in the loop's own thread, a simulated second at a time. The
BLF gets each batch of frames as one array of BLF objects, no ``can.Message`` per frame, and
compresses its containers at zlib level 1 (:class:`~cosim.results.can_logs.FrameBlfWriter`); the
time series is formatted with one ``%`` per row (:func:`~cosim.results.writer.timeseries_lines`).
Other log formats take python-can's writers frame by frame. Measured on 2026-12-02 (the same run
of the benchmark, each side after one full garbage collection): ``crd run`` at 0.93-0.94 of the
loop alone this way, the writing 5.5-5.8 % of the loop's CPU time (zlib, the time series' float
formatting and packing the BLF objects about a quarter each), against 0.72-0.76 with the writing
on a background thread (issue 25's first design): the thread's formatting and packing hold the
GIL in turns with the loop, and the hand-overs between the two threads cost more than the writing
itself (about 12 % of the loop's CPU time). A write that fails (a full disk) stops
the run with :class:`LogWriteError`, naming the run's directory and the cause, and what was written
before is kept (``tests/cosim/test_log_writer.py``).
"""

from __future__ import annotations

import csv
import os
from datetime import datetime
from pathlib import Path
from typing import Iterable, Sequence

import can
from can.io.generic import FileIOMessageWriter

from ..errors import ConfigError, CosimError
from .can_logs import FrameBlfWriter, open_python_can_writer, streamed, write_can_logs
from .held_signals import signals_held
from .run_record import TIMESERIES_COLUMNS, RunRecord
from .writer import timeseries_lines


class LogWriteError(CosimError, RuntimeError):
    """A run's logs could not be written (the cause: the exception the write met)."""


def check_out_dir(out_dir: Path, subdirs: Iterable[str] = ()) -> None:
    """ConfigError naming the path unless ``out_dir`` (and ``out_dir/<sub>``) can be created and written.

    Creates nothing (a run refused later for another reason leaves no directory behind): every
    existing part of each path must be a directory, and the deepest existing one writable.
    """
    out_dir = Path(out_dir)
    for path in [out_dir, *(out_dir / s for s in subdirs)]:
        parts = [*reversed(path.parents), path]
        blocker = next((p for p in parts if p.exists() and not p.is_dir()), None)
        if blocker is not None:
            raise ConfigError(f"--out {out_dir}: cannot write results under {blocker}: it is a file, not a directory")
        deepest = [p for p in parts if p.exists()][-1]
        if not os.access(deepest, os.W_OK | os.X_OK):
            raise ConfigError(f"--out {out_dir}: cannot write results in {deepest}: permission denied")


class RunStream:
    """One run's ``timeseries.csv`` and CAN logs, written while it runs (see the module docstring).

    Every log python-can writes (BLF, ASC, TRC, ``.log``, CSV) is streamed; an MF4 log
    (asammdf) is written from the record when the stream closes.
    """

    def __init__(self, run_dir: Path, can_logs: Sequence[str], start: datetime,
                 columns: Sequence[str] = TIMESERIES_COLUMNS) -> None:
        run_dir.mkdir(parents=True, exist_ok=True)
        self._run_dir, self._start, self._start_s = run_dir, start, start.timestamp()
        self._rows = self._frames = 0
        self._at_end = [name for name in can_logs if not streamed(name)]
        self._writers: list = []
        self._csv_file = open(run_dir / "timeseries.csv", "w", newline="")
        try:
            csv.writer(self._csv_file).writerow(columns)
            for name in can_logs:
                if streamed(name):
                    self._writers.append(open_python_can_writer(run_dir / name, start))
            self._blf = [w for w in self._writers if isinstance(w, FrameBlfWriter)]  # BLF: in bulk
            self._per_message = [w.on_message_received for w in self._writers if not isinstance(w, FrameBlfWriter)]
        except BaseException:
            self._stop_all()
            raise
        self.closed = self._failed = False

    def flush(self, record: RunRecord) -> None:
        """Write ``record``'s rows and frames added since the last call and pass them to the OS; raises
        :class:`LogWriteError` if the write fails (once: after it, nothing more is written).

        A signal meanwhile is held until the write is whole (:mod:`cosim.results.held_signals`).
        """
        if self._failed:
            return
        rows, frames = record.rows, record.frames
        new_rows, new_frames = rows[self._rows:], frames[self._frames:]
        self._rows, self._frames = len(rows), len(frames)
        with signals_held():
            try:
                self._write(new_rows, new_frames, record.columns)
            except Exception as exc:  # noqa: BLE001 - any failed write stops the run, named
                self._failed = True
                raise LogWriteError(f"{self._run_dir}: writing the logs failed: {exc}") from exc

    def _write(self, rows: list, frames: list, columns: Sequence[str]) -> None:
        """One batch of rows and frames into every file, passed to the OS."""
        start_s = self._start_s
        self._csv_file.write(timeseries_lines(rows, columns))
        for blf in self._blf:  # the batch in one array of BLF objects, no can.Message (can_logs.FrameBlfWriter)
            blf.write_frames(frames, start_s)
        if self._per_message:  # one can.Message per frame, shared by every writer
            for f in frames:
                msg = can.Message(timestamp=start_s + f.t_s, arbitration_id=f.arbitration_id, data=f.data,
                                  is_extended_id=False, channel=0)
                for log in self._per_message:
                    log(msg)
        self._csv_file.flush()
        for writer in self._writers:
            if isinstance(writer, can.BLFWriter):
                writer._flush()  # noqa: SLF001 - python-can has no public call to close the current container
            if isinstance(writer, FileIOMessageWriter):
                writer.file.flush()

    def close(self, record: RunRecord | None) -> None:
        """Write the rest of ``record`` (None: nothing more), close the files, write the MF4 logs; idempotent.
        The files are closed whatever happens; a failed write is raised after."""
        if self.closed:
            return
        self.closed = True
        try:
            if record is not None:
                self.flush(record)
        finally:
            self._stop_all()
        if record is not None and self._at_end:
            write_can_logs(self._run_dir, record, self._at_end, self._start)

    def _stop_all(self) -> None:
        try:
            for writer in self._writers:
                writer.stop()
        finally:
            self._csv_file.close()
