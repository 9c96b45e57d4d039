"""A SIGINT or SIGTERM ends a run between two co-simulation cycles, never within one.

Raised mid-cycle (between the cycle's logged frames and its time-series row), it left the
run's ``can.blf`` one cycle longer than its ``timeseries.csv`` (1 in 28 interrupted runs
under load, ``tests/robustness/test_results_survive.py``). Here the signal is raised at
exactly that point, every time, by the frame log itself.
"""

from __future__ import annotations

import signal

import pytest

from cosim.loop.master import ClosedLoop
from cosim.results.held_signals import SafePoints
from cosim.scenarios.loader import scenario_from_dict


class _SignalAt(list):
    """A frame log that raises ``sig`` to this process when its ``at``-th frame is appended."""

    def __init__(self, at: int, sig: int) -> None:
        super().__init__()
        self.at, self.sig = at, sig

    def append(self, frame) -> None:
        super().append(frame)
        if len(self) == self.at:
            signal.raise_signal(self.sig)


def test_a_signal_in_the_middle_of_a_cycle_ends_the_run_after_that_cycle(plant_fmu3):
    sc = scenario_from_dict({"scenario": {"name": "s", "duration_s": 5.0}, "ecu": {"strategy": "tightening"}})
    loop = ClosedLoop(sc, plant_fmu3, "tightening")
    loop.record.frames = _SignalAt(1001, signal.SIGINT)  # the first frame of a cycle: its row not yet logged
    record = loop.run()
    assert record.interrupted == "SIGINT"
    frame_times = sorted({f.t_s for f in record.frames})
    row_times = [row[0] for row in record.rows]
    assert len(record.frames) > 1001 and frame_times == row_times  # every logged cycle whole: frames and row
    assert record.events[-1].kind == "interrupted" and 0.0 < row_times[-1] < 5.0


def test_safe_points_note_a_signal_and_act_on_it_when_asked():
    before = signal.getsignal(signal.SIGINT)
    with SafePoints() as points:
        signal.raise_signal(signal.SIGINT)  # noted, not raised
        assert points.noted == [signal.SIGINT]
        with pytest.raises(KeyboardInterrupt):
            points.act()
        assert signal.getsignal(signal.SIGINT) is before  # restored at act()
    assert signal.getsignal(signal.SIGINT) is before


def test_a_second_signal_or_the_end_of_the_block_acts_at_once():
    with pytest.raises(KeyboardInterrupt):
        with SafePoints():
            signal.raise_signal(signal.SIGINT)
            signal.raise_signal(signal.SIGINT)  # a second one: raised here, the loop may be blocked
            pytest.fail("not reached")
    with pytest.raises(KeyboardInterrupt):
        with SafePoints():
            signal.raise_signal(signal.SIGINT)  # noted, and the block ends before a safe point
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_an_ignored_signal_stays_ignored_and_a_handler_that_returns_is_called_once():
    calls = []
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with SafePoints() as points:
            signal.raise_signal(signal.SIGINT)
            assert points.noted == []  # not held: ignored, as before the block
        signal.signal(signal.SIGINT, lambda signum, frame: calls.append(signum))
        with SafePoints() as points:
            signal.raise_signal(signal.SIGINT)
            for _ in range(3):  # three safe points: acted on at the first only
                if points.noted:
                    points.act()
        assert calls == [signal.SIGINT]
    finally:
        signal.signal(signal.SIGINT, previous)
