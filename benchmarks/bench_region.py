"""Stopping-region core (issue 22, item 1): ``decide`` with 8 tracks, median µs per call.

    python benchmarks/bench_region.py                 # 7 rounds of 2000 calls per case
    python benchmarks/bench_region.py --rounds 3 --calls 500

Cases, alternating round by round with today's 1-D core step (bench_ecu's input) so that a loaded
machine shifts all of them alike; the ratio to the 1-D step is the load-robust figure:

* ``nominal``: 8 tracks, the driver's path disjoint (rule 1; only the driver's, nominal and lane rows
  are built), the wheel turned (yaw rate 0.05 rad/s): the every-cycle case;
* ``nominal-straight``: the same with yaw rate 0 and a straight road;
* ``emergency``: 8 tracks, a stopped car ahead that braking cannot avoid: the 13 steering rows, road
  and lane test, the choice;
* ``sat-2axis`` / ``sat-4axis``: the separation of the emergency family alone, as used (the pose's two
  axes, and the objects' two where those do not separate: here, as in every cycle with an overlap,
  both) and the full separating-axis test everywhere;
* ``step-8-tracks``: the whole core step (``ecu.core.step``, the region wired, ``ecu.core.planar``) with
  the ``nominal`` tracks as RadarTrack slots, the wheel turned; ``step-8-tracks-urgent``: the
  ``emergency`` tracks with steering authority (the steering rows searched every cycle).

Goal (issue 22): the whole core step with 8 tracks <= 100 µs, so <= 60 µs for this part.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_ecu import bench_core  # noqa: E402

from ecu.core import CoreParams  # noqa: E402
from ecu.core.region import EgoState, Road, TrackBox, decide, region_params  # noqa: E402
from ecu.core.region.objects import object_set  # noqa: E402
from ecu.core.region.overlap import footprint, gaps  # noqa: E402
from ecu.core.region.paths import path_family  # noqa: E402

CORE = CoreParams()
PARAMS = region_params(CORE)
ROAD = Road((-1.75, 1.75, 5.25, 8.75))
D = CORE.model_decel_mps2


def _tracks(lead_x_m: float, speed_mps: float) -> list[TrackBox]:
    """A lead object ahead, oncoming and same-direction cars in the other lanes, pedestrians at the kerb."""
    lead = TrackBox(lead_x_m, 0.0, -speed_mps, 0.0, 4, 0.1)
    others = [TrackBox(70.0, 3.5, -speed_mps - 15.0, 0.0, 4, 0.2), TrackBox(90.0, 7.0, -5.0, 0.0, 4, 0.2),
              TrackBox(45.0, -3.0, -speed_mps, 0.0, 1, 0.1), TrackBox(60.0, -2.6, -speed_mps, 1.2, 1, 0.1),
              TrackBox(110.0, 3.8, -speed_mps, 0.0, 4, 0.3), TrackBox(35.0, 9.0, -speed_mps + 4.0, 0.0, 2, 0.1),
              TrackBox(130.0, -0.2, -speed_mps + 10.0, 0.0, 5, 0.3)]
    return [lead, *others]


def _sat_4axis(paths, objects, box):
    """The full separating-axis test: the pose's axes and the object's (measurement only)."""
    g2 = gaps(paths, objects, box)
    heading = paths.heading[..., None]
    local = (paths.position[..., None] - objects.centre) * objects.axis_conj  # pose in the object's frame
    turn = heading * objects.axis_conj
    rc, rs = np.abs(turn.real), np.abs(turn.imag)
    offset = box.mid_x_m * turn  # footprint centre offset along the pose's heading, in the object's frame
    hx = box.half_x_m * rc + box.half_y_m * rs
    hy = box.half_x_m * rs + box.half_y_m * rc
    gx = np.abs(local.real + offset.real) - objects.half_length_m - hx
    gy = np.abs(local.imag + offset.imag) - objects.half_width_m - hy
    return np.maximum(g2, np.maximum(gx, gy))


def _cases() -> dict:
    wheel = math.atan(0.05 / 20.0 * PARAMS.wheelbase_m)  # the wheel as the yaw rate: a steady turn
    ego_turning, ego_straight = EgoState(20.0, 1.0, D, 0.05, wheel), EgoState(20.0, 1.0, D)
    ego_fast = EgoState(30.0, 0.0, D)
    calm, urgent = _tracks(80.0, 20.0), _tracks(58.0, 30.0)
    fam = path_family(ego_fast, 0.0, PARAMS)
    objs, box = object_set(urgent, 30.0, PARAMS), footprint(fam, PARAMS)
    assert decide(ego_turning, calm, ROAD, PARAMS).kind.name == "DRIVER_PATH"
    assert decide(ego_straight, calm, ROAD, PARAMS).kind.name == "DRIVER_PATH"
    assert decide(ego_fast, urgent, ROAD, PARAMS).kind.name in ("STEER_AND_BRAKE", "LEAST_IMPACT")
    return {"nominal": lambda: decide(ego_turning, calm, ROAD, PARAMS),
            "nominal-straight": lambda: decide(ego_straight, calm, ROAD, PARAMS),
            "emergency": lambda: decide(ego_fast, urgent, ROAD, PARAMS),
            "sat-2axis": lambda: gaps(fam, objs, box),
            "sat-4axis": lambda: _sat_4axis(fam, objs, box),
            "step-8-tracks": _step_case(calm, 20.0, 0.05 * 20.0 / 20.0, CORE),
            "step-8-tracks-urgent": _step_case(urgent, 30.0, 0.0, CoreParams(steering_authority=True))}


def _step_case(boxes: list[TrackBox], speed_mps: float, yaw_rate: float, params: CoreParams):
    """The whole core step, settled, with ``boxes`` as the contract's tracks (the ObjectTrack empty)."""
    from can_dbc.planar import Track
    from ecu.core import CoreInputs, CoreState, step

    tracks = tuple(Track(i, b.size_class, 7, b.x_m, b.y_m, b.vx_mps, b.vy_mps) for i, b in enumerate(boxes))
    wheel_rad = params.steering_ratio * math.atan(yaw_rate / speed_mps * params.region.wheelbase_m)  # a steady turn

    def inputs(t_s: float) -> CoreInputs:
        return CoreInputs(t_s=t_s, wheel_speeds_mps=(speed_mps,) * 4, accel_pedal=0.2, wheel_rx_t_s=t_s,
                          driver_rx_t_s=t_s, object_rx_t_s=t_s, tracks=tracks, yaw_rate_radps=yaw_rate,
                          steering_wheel_rad=wheel_rad)

    state = CoreState()
    for k in range(30):
        state, _ = step(state, inputs(k * 0.01), params)
    cycle = inputs(0.3)
    return lambda: step(state, cycle, params)


def _median_us(fn, calls: int) -> float:
    clock, times = time.perf_counter, []
    for _ in range(calls):
        start = clock()
        fn()
        times.append(clock() - start)
    return statistics.median(times) * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--calls", type=int, default=2000)
    args = parser.parse_args()
    cases = _cases()
    results: dict[str, list[float]] = {name: [] for name in ("1-D core step", *cases)}
    for _ in range(args.rounds):
        results["1-D core step"].append(bench_core(args.calls) * 1e6)
        for name, fn in cases.items():
            results[name].append(_median_us(fn, args.calls))
    base = statistics.median(results["1-D core step"])
    print(f"load average {' '.join(f'{x:.2f}' for x in os.getloadavg())}; {args.rounds} rounds x {args.calls} calls, "
          f"alternating; median of the per-round medians (min..max), ratio to the 1-D core step")
    for name, values in results.items():
        med = statistics.median(values)
        print(f"  {name:18s} {med:8.1f} us  ({min(values):.1f}..{max(values):.1f})  x{med / base:5.2f}")


if __name__ == "__main__":
    main()
