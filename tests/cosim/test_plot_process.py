"""The plot process of ``crd paper`` (:class:`cosim.loop.plot_process.PlotProcess`): forked from this process, it
draws what it is given in its own process group with SIGINT/SIGTERM blocked (a terminal's Ctrl-C reaches crd
alone, and a figure it was given is drawn whole); the heap frozen for the fork is unfrozen here at once."""

from __future__ import annotations

import gc
import os
import signal

import pytest

from cosim.loop.plot_process import PlotProcess

MODULE_LEVEL_MARK = "inherited through the fork"


def _where() -> tuple[int, int, set[int], str]:
    return os.getpid(), os.getpgid(0), set(signal.pthread_sigmask(signal.SIG_BLOCK, [])), MODULE_LEVEL_MARK


def test_draws_in_its_own_process_group_with_the_signals_blocked():
    frozen_before = gc.get_freeze_count()
    with PlotProcess() as plots:
        plots.start()
        assert gc.get_freeze_count() == frozen_before  # unfrozen here after the fork
        pid, group, blocked, mark = plots.submit(_where).result(timeout=60)
    assert pid != os.getpid() and group == pid
    assert {signal.SIGINT, signal.SIGTERM} <= blocked
    assert mark == MODULE_LEVEL_MARK


def test_submit_before_start_is_an_error():
    with PlotProcess() as plots, pytest.raises(RuntimeError, match="before start"):
        plots.submit(_where)
