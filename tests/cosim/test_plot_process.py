"""The plot process of ``crd paper`` (:class:`cosim.loop.plot_process.PlotProcess`): forked from this process, it
draws what it is given in its own process group with SIGINT/SIGTERM blocked (a terminal's Ctrl-C reaches crd
alone, and a figure it was given is drawn whole)."""

from __future__ import annotations

import os
import signal

import pytest

from cosim.loop.plot_process import PlotProcess

def _where() -> tuple[int, int, set[int]]:
    return os.getpid(), os.getpgid(0), set(signal.pthread_sigmask(signal.SIG_BLOCK, []))


def test_draws_in_its_own_process_group_with_the_signals_blocked():
    with PlotProcess() as plots:
        plots.start()
        pid, group, blocked = plots.submit(_where).result(timeout=60)
    assert pid != os.getpid() and group == pid
    assert {signal.SIGINT, signal.SIGTERM} <= blocked


def test_submit_before_start_is_an_error():
    with PlotProcess() as plots, pytest.raises(RuntimeError, match="before start"):
        plots.submit(_where)
