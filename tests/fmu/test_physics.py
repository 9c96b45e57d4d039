"""Plant physics against analytic references; each tolerance is stated in the test.

Defaults (fmu_plant/README.md): m 1500 kg, r 0.31 m, Cd*A 0.65 m^2, rho 1.2 kg/m^3,
Crr 0.012, J 1.0 kg m^2 per wheel, tyre D 0.9, T_d 0.10 s, tau 0.12 s.
"""

import math

import numpy as np
import pytest
from fmpy import read_model_description

from tests.fmu.plant_runner import run_plant

G = 9.80665
V100 = 100 / 3.6


@pytest.fixture(scope="module")
def defaults(fmu2) -> dict[str, float]:
    md = read_model_description(str(fmu2))
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and v.type == "Real"}


def brake_run(fmu2, friction, abs_enabled=True):
    return run_plant(fmu2, 2, 14.0, 0.01, lambda t: {"brake": 1.0, "road_friction": friction},
                     params={"v0": V100, "abs_enabled": abs_enabled})


def stop_distance(run) -> float:
    stopped = np.flatnonzero(run["v"] <= 0.0)
    assert stopped.size, "the car never stopped"
    return run["x"][stopped[0]]


def analytic_stop(v, dead_s, tau_s, decel):
    """v (T_d + tau) + v^2 / (2 A) - A tau^2 / 2: dead time, first-order build-up, then A."""
    return v * (dead_s + tau_s) + v * v / (2 * decel) - decel * tau_s**2 / 2


def test_full_throttle_reaches_100_kmh_in_6_to_11_s(fmu2):
    run = run_plant(fmu2, 2, 15.0, 0.01, lambda t: {"throttle": 1.0})
    t100 = run["t"][np.argmax(run["v"] >= V100)]
    assert run["v"].max() >= V100
    assert 6.0 <= t100 <= 11.0, f"0-100 km/h took {t100} s"


def test_abs_stop_from_100_kmh_lies_within_the_analytic_band(fmu2, defaults):
    """Upper bound: A = 0.85 mu D g (ABS efficiency >= 85 %). Lower bound: A = mu D g plus
    drag and rolling resistance at 100 km/h, which no tyre can beat."""
    p = defaults
    d = stop_distance(brake_run(fmu2, 1.0))
    peak = p["tyre_D"] * G
    a_max = peak + 0.5 * p["air_density"] * p["drag_area"] * V100**2 / p["mass"] + p["rolling_resistance"] * G
    upper = analytic_stop(V100, p["brake_dead_time"], p["brake_time_constant"], 0.85 * peak)
    lower = analytic_stop(V100, p["brake_dead_time"], p["brake_time_constant"], a_max)
    assert lower <= d <= upper, f"stop {d:.2f} m outside [{lower:.2f}, {upper:.2f}] m"


def test_half_friction_roughly_doubles_the_braking_distance(fmu2, defaults):
    """Braking part = distance after the dead time; analytic ratio from the formula with A
    halved; tolerance 10 % of that ratio."""
    p = defaults
    dead = p["brake_dead_time"] * V100
    ratio = (stop_distance(brake_run(fmu2, 0.5)) - dead) / (stop_distance(brake_run(fmu2, 1.0)) - dead)
    a = 0.9 * p["tyre_D"] * G
    expect = ((analytic_stop(V100, 0, p["brake_time_constant"], a / 2))
              / analytic_stop(V100, 0, p["brake_time_constant"], a))
    assert 1.8 < expect < 2.0
    assert ratio == pytest.approx(expect, rel=0.10)


def test_without_abs_the_wheels_lock_and_with_abs_they_do_not(fmu2, defaults):
    r = defaults["wheel_radius"]
    locked = brake_run(fmu2, 1.0, abs_enabled=False)
    fast = locked["v"] > 10.0
    for wheel in ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr"):
        assert (locked[wheel][fast] == 0.0).any(), f"{wheel} never locked"
    cycling = brake_run(fmu2, 1.0, abs_enabled=True)
    moving = cycling["v"] > 3.0
    for wheel in ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr"):
        ratio = cycling[wheel][moving] * r / cycling["v"][moving]
        assert ratio.min() > 0.7, f"{wheel} slip reached {1 - ratio.min():.2f} with ABS"


def test_coast_down_matches_drag_plus_rolling_resistance(fmu2, defaults):
    """a = -(rho CdA v^2 / 2 + Crr m g) / (m + 4 J / r^2); tolerance 1 %."""
    p = defaults
    run = run_plant(fmu2, 2, 3.0, 0.01, params={"v0": 30.0})
    m_eff = p["mass"] + 4 * p["wheel_inertia"] / p["wheel_radius"] ** 2
    for k in (100, 200, 300):  # after the first second
        v = run["v"][k]
        expect = -(0.5 * p["air_density"] * p["drag_area"] * v * v
                   + p["rolling_resistance"] * p["mass"] * G) / m_eff
        assert run["a"][k] == pytest.approx(expect, rel=0.01)


def test_steady_cruise_wheel_speed_times_radius_equals_v(fmu2, defaults):
    p = defaults
    v0 = 25.0
    resist = 0.5 * p["air_density"] * p["drag_area"] * v0**2 + p["rolling_resistance"] * p["mass"] * G
    throttle = resist / p["max_drive_force"]
    run = run_plant(fmu2, 2, 20.0, 0.05, lambda t: {"throttle": throttle}, params={"v0": v0})
    late = run["t"] >= 1.0
    assert abs(run["v"][-1] - v0) < 1.0  # it really cruises
    for wheel in ("wheel_speed_fl", "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr"):
        ratio = run[wheel][late] * p["wheel_radius"] / run["v"][late]
        assert np.abs(ratio - 1.0).max() < 0.005, wheel


def test_standstill_stays_at_rest(fmu2):
    run = run_plant(fmu2, 2, 10.0, 0.05, params={"x0": 12.5})
    assert (run["x"] == 12.5).all() and (run["v"] == 0.0).all() and (run["a"] == 0.0).all()
    assert (run["wheel_speed_fl"] == 0.0).all() and (run["wheel_speed_rr"] == 0.0).all()


def test_uphill_without_brakes_never_rolls_backwards(fmu2):
    run = run_plant(fmu2, 2, 10.0, 0.05, lambda t: {"grade": 0.2})
    assert (run["x"] == 0.0).all() and (run["v"] == 0.0).all()


def test_after_braking_to_a_stop_the_car_rests_without_chatter(fmu2):
    def schedule(t):
        return {"brake": 1.0 if t < 6.0 else 0.0, "grade": 0.1 if t >= 6.0 else 0.0}

    run = run_plant(fmu2, 2, 10.0, 0.001, schedule, params={"v0": 10.0})
    stopped = np.argmax(run["v"] == 0.0)
    assert 0 < run["t"][stopped] < 3.0
    after = slice(stopped + 1, None)  # sample `stopped` still carries the last deceleration
    assert (run["v"][after] == 0.0).all() and (run["a"][after] == 0.0).all()
    assert (run["x"][after] == run["x"][stopped]).all()  # no creep, no reversing on the slope
    assert (run["wheel_speed_fl"][after] == 0.0).all() and (run["wheel_speed_rl"][after] == 0.0).all()


def test_brake_dead_time_delays_any_deceleration(fmu2, defaults):
    run = run_plant(fmu2, 2, 1.0, 0.001, lambda t: {"brake": 1.0}, params={"v0": 20.0})
    coast = -(0.5 * defaults["air_density"] * defaults["drag_area"] * 400
              + defaults["rolling_resistance"] * defaults["mass"] * G) / defaults["mass"]
    before = run["t"] <= defaults["brake_dead_time"]
    assert run["brake_pressure"][before].max() == 0.0
    assert run["a"][before].min() > coast * 1.1
    assert run["brake_pressure"][-1] > 0.9 * defaults["max_brake_force"]


def test_drive_force_lingers_after_the_throttle_closes(fmu2, defaults):
    """Below the power limit the drive force decays as exp(-t / tau); tolerance 1 %."""
    run = run_plant(fmu2, 2, 4.0, 0.001, lambda t: {"throttle": 0.3 if t < 3.0 else 0.0})
    tau = defaults["throttle_time_constant"]
    k_close = int(round(3.0 / 0.001))
    assert run["drive_force"][k_close] == pytest.approx(0.3 * defaults["max_drive_force"], rel=1e-3)
    k_tau = k_close + int(round(tau / 0.001))
    assert run["drive_force"][k_tau] / run["drive_force"][k_close] == pytest.approx(math.exp(-1), rel=0.01)
