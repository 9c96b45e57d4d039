"""Profiling wraps the loop's collaborators in timers; the run itself is the same (about 2 s)."""

from __future__ import annotations

import dataclasses

from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.master import PHASES, ClosedLoop, run_scenario
from cosim.loop.phase_timer import PhaseTimer, Timed
from cosim.scenarios.loader import load_scenario


def test_profiled_run_is_the_same_run_with_a_cost_per_phase(plant_fmu3):
    sc = load_scenario(PAPER_SCENARIO)
    sc = dataclasses.replace(sc, scenario=dataclasses.replace(sc.scenario, duration_s=3.0))
    plain = run_scenario(sc, plant_fmu3, "tightening")
    loop = ClosedLoop(sc, plant_fmu3, "tightening", profile=True)
    assert isinstance(loop.plant, Timed) and isinstance(loop.link, Timed)
    profiled = loop.run()
    assert profiled.rows == plain.rows and profiled.frames == plain.frames
    assert plain.cycle_cost_s == {}
    assert set(profiled.cycle_cost_s) == set(PHASES)
    assert all(profiled.cycle_cost_s[p] > 0.0 for p in ("fmu", "codec", "bus", "ecu", "logging"))


def test_nested_timed_calls_are_charged_to_their_own_phase(monkeypatch):
    import cosim.loop.phase_timer as pt

    clock = iter(range(0, 1000, 10))
    monkeypatch.setattr(pt.time, "perf_counter_ns", lambda: next(clock))
    timer = PhaseTimer()  # its timers read the fake clock: 0, 10, 20, 30, ...
    inner = timer.timed("ecu", lambda: None)
    outer = timer.timed("bus", inner)
    outer()  # bus from 0 to 30, ecu inside it from 10 to 20
    assert timer.ns["ecu"] == 10 and timer.ns["bus"] == 20
    assert timer.per_cycle_s(1)["bus"] == 20e-9
