"""Brakes that release faster than they apply (issue 14's candidate), in both FMI versions.

A falling brake command reaches the pressure after ``f_d * T_d`` and decays with
``f_tau * tau``; a rising one still waits ``T_d`` and builds with ``tau``. At the
defaults (both fractions 1) release mirrors build-up. Time resolution: the 1 ms grid,
so every instant below is allowed 2 ms.
"""

import math

import numpy as np
import pytest

from tests.fmu.plant_runner import run_plant

T_D, TAU = 0.10, 0.12  # the plant's brake_dead_time and brake_time_constant defaults (s)
RELEASE_S, REAPPLY_S = 1.0, 1.5
GRID_S = 0.002


def pulse(t: float) -> dict[str, float]:
    """Full brake until RELEASE_S, none until REAPPLY_S, full again (a standing car)."""
    return {"brake": 0.0 if RELEASE_S <= t < REAPPLY_S else 1.0}


def decay(run, after_s: float) -> tuple[float, float]:
    """(delay until the pressure first falls after ``after_s``, the index of that first fall)."""
    t, p = run["t"], run["brake_pressure"]
    k0 = int(np.argmax(t >= after_s))
    start = k0 + int(np.argmax(p[k0:] < p[k0]))
    return t[start] - after_s, start


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("f_dead, f_tau", [(1.0, 1.0), (0.2, 1 / 3), (0.0, 0.25)])
def test_release_delay_and_decay_follow_the_fractions(fmus, version, f_dead, f_tau):
    params = {"brake_release_dead_time_fraction": f_dead, "brake_release_time_constant_fraction": f_tau}
    run = run_plant(fmus[version], version, 2.0, 0.001, pulse, params=params)
    p = run["brake_pressure"]
    delay_s, start = decay(run, RELEASE_S)
    assert f_dead * T_D <= delay_s + 1e-9 <= f_dead * T_D + GRID_S
    tau_r = f_tau * TAU
    later = start + int(round(tau_r / 0.001))
    lo, hi = math.exp(-(tau_r + GRID_S) / tau_r), math.exp(-(tau_r - GRID_S) / tau_r)
    assert lo <= p[later] / p[start - 1] <= hi
    # the rising edge still waits the full dead time, whatever the release does
    k_up = int(np.argmax(run["t"] >= REAPPLY_S))
    k_rise = k_up + int(np.argmax(np.diff(p[k_up:]) > 0.0))
    assert T_D <= run["t"][k_rise] - REAPPLY_S + 1e-9 <= T_D + GRID_S


def test_default_fractions_reproduce_the_symmetric_brake_bit_for_bit(fmus):
    """Fractions 1 take exactly the old path: the same trajectory as not naming them at all."""
    sym = run_plant(fmus[3], 3, 2.0, 0.01, pulse, params={"v0": 20.0})
    named = run_plant(fmus[3], 3, 2.0, 0.01, pulse, params={
        "v0": 20.0, "brake_release_dead_time_fraction": 1.0, "brake_release_time_constant_fraction": 1.0})
    fast = run_plant(fmus[3], 3, 2.0, 0.01, pulse, params={"v0": 20.0, "brake_release_dead_time_fraction": 0.2})
    for name in ("x", "v", "brake_pressure"):
        assert np.array_equal(sym[name], named[name])
    assert not np.array_equal(sym["brake_pressure"], fast["brake_pressure"])  # the knob is live
