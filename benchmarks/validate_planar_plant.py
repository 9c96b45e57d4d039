"""The planar plant FMU against the independent CommonRoad ST model (issue 21): prints a table.

Same parameters in both (CommonRoad vehicle 2 with the plant's mass, geometry, yaw inertia and CG
height; the plant's steering lag set to 0); the machinery and its conventions are in
``tests/fmu/planar_reference.py``, the pass criteria in ``tests/fmu/test_planar_validation.py``.

* ISO 4138 steady-state circle (constant steering-wheel angle, 100 m kinematic radius) at 0.3 g
  and 0.6 g: yaw rate and lateral acceleration (goal: within 2 %), sideslip and rear slip angle;
* ISO 7401 step steer at 80 km/h to 4 m/s^2: yaw-rate peak (goal: within 5 %), overshoot and
  response time (goal: within 10 %);
* ISO 3888-2 double lane change at 60 km/h driven by the pure-pursuit driver
  (cosim/world/path_following.py): wheel margins to the cones per gate (goal: > 0) and the
  largest lateral distance between the two tracks (goal: <= 0.2 m).

Run: python benchmarks/validate_planar_plant.py  (needs the ``test`` extra: commonroad-vehicle-models)
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))  # the repository, for tests.fmu

from fmu_plant.build import ensure_fmu  # noqa: E402
from tests.fmu.planar_reference import (double_lane_change, rear_slip_ratio_expected, steady_state,  # noqa: E402
                                        step_steer)


def _row(label: str, plant: float, st: float, unit: str, goal: str = "") -> str:
    diff = (plant / st - 1.0) * 100.0 if st else float("nan")
    return f"| {label} | {plant:.4f} | {st:.4f} | {unit} | {diff:+.2f} % | {goal} |"


def main() -> None:
    fmu = ensure_fmu(fmi_version=2)
    print("| figure | plant FMU | CommonRoad ST | unit | plant vs ST | goal |")
    print("|---|---|---|---|---|---|")
    for ay_g in (0.3, 0.6):
        r = steady_state(fmu, ay_g)
        head = f"ISO 4138 {ay_g} g ({r['speed_mps']:.2f} m/s, delta {r['delta_rad']:.4f} rad):"
        print(_row(f"{head} yaw rate", r["plant_yaw_rate"], r["st_yaw_rate"], "rad/s", "within 2 %"))
        print(_row(f"{head} lateral acceleration", r["plant_ay"], r["st_ay"], "m/s^2", "within 2 %"))
        print(_row(f"{head} sideslip beta", r["plant_beta"], r["st_beta"], "rad"))
        ratio = rear_slip_ratio_expected(fmu, ay_g)
        print(_row(f"{head} rear slip angle", r["plant_alpha_rear"], r["st_alpha_rear"], "rad",
                   f"tyre curves predict {100 * (ratio - 1):+.2f} %"))
    r = step_steer(fmu)
    head = f"ISO 7401 step, 80 km/h, delta {r['delta_rad']:.4f} rad:"
    print(_row(f"{head} yaw-rate peak", r["plant_peak"], r["st_peak"], "rad/s", "within 5 %"))
    print(f"| {head} yaw-rate overshoot | {100 * r['plant_overshoot']:.4f} | {100 * r['st_overshoot']:.4f} | % | | "
          "none: no peak to time |")
    print(_row(f"{head} response time (50 % steer to 90 % yaw rate)", r["plant_response_s"], r["st_response_s"],
               "s", "within 10 %"))
    print(_row(f"{head} steady lateral acceleration", r["plant_ay_steady"], r["st_ay_steady"], "m/s^2"))
    r = double_lane_change(fmu)
    for i, (mp, ms) in enumerate(zip(r["plant_margins_m"], r["st_margins_m"]), start=1):
        print(f"| ISO 3888-2, 60 km/h: wheel margin in gate {i} | {mp:.3f} | {ms:.3f} | m | | > 0 |")
    print(_row("ISO 3888-2, 60 km/h: peak lateral acceleration", r["plant_ay_max"], r["st_ay_max"], "m/s^2"))
    print(f"| ISO 3888-2, 60 km/h: largest distance between the tracks | {r['track_gap_m']:.3f} | | m | "
          f"| <= 0.2 m |")
    print(f"| ISO 3888-2, 60 km/h: speed at the exit (throttle released at the entry) | "
          f"{r['speed_exit_mps']:.2f} | | m/s | | |")


if __name__ == "__main__":
    main()
