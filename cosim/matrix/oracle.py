"""The offline oracle of issue 22: could the car have avoided contact once its radar confirmed the object?

For one planar cell, in the true closed loop (the true plant, the true scene, the scenario's driver) with
the ECU disconnected (the actuators never hear it):

1. **baseline**: the cell as it runs with no ECU. No contact: nothing to avoid. Otherwise the
   object touched is the one to avoid;
2. **confirmation time** ``t_c``: the radar cycle at which the 2-D radar (``cosim.world.radar_tracks``)
   has reported that object in ``confirm_reports`` consecutive reports, the ECU's own rule
   (``[ecu] track_confirm_reports``, 3 of the DBC's 50 ms cycle; :mod:`ecu.core.track_confirmation`);
   the radar's latency is in the reports' timing already;
3. **search**: from ``t_c`` on, the driver's pedals and wheel are replaced by one manoeuvre of
   :data:`GRID`: a constant brake pedal, and on the wheel (from its angle at ``t_c``) either nothing or
   an evasive lane change, the double pulse ``+offset`` for ``T`` then ``-offset`` for ``T``, then back.
   ``T`` is the kinematic single-track's time for one lane width, ``y = v^2 delta T^2 / L`` at the speed at
   ``t_c`` (``delta`` the road-wheel offset, wheel angle over the steering ratio ``STEERING_RATIO``; the
   true plant, with its steering-rate limit, its tyres and the braking, decides what really happens);
   after it the wheel holds the course the car had at ``t_c`` (:func:`_evasion_rad`).
   The search stops at the first manoeuvre that avoids: no contact with any object and no road
   departure (the box never beyond the road's edge). The grid tries braking straight first, then each
   lane change with full braking, then with less.

The oracle is exact for the plant and the scene (it runs them), not for the ECU's knowledge: it is the
best any controller limited to the grid could have done from ``t_c``. A cell it cannot clear is one
where no manoeuvre of the grid avoids; a finer grid could still find one (its resolution is stated).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping

from ..loop.master import ClosedLoop
from ..scenarios.loader import scenario_from_dict
from ..world.driver_models import Pedals
from .runner import outcome_of
from .scoring import Outcome

#: the lane changes' wheel offsets (steering-wheel angle, deg), each side: the more, the shorter the change
WHEEL_OFFSETS_DEG = (30.0, 60.0, 90.0, 135.0, 180.0, 270.0)
#: the brake pedal levels tried (%), hardest first
BRAKE_LEVELS_PCT = (100.0, 50.0, 0.0)
#: the lateral displacement a lane change aims at (m): Euro NCAP's and crd's catalogue lane width
LANE_WIDTH_M = 3.5
#: the kinematic model of the pulse length: the crd plant's wheelbase and steering ratio (fmu_plant/README.md)
WHEELBASE_M, STEERING_RATIO = 2.7, 16.0
#: after the lane change, the road-wheel angle per rad of heading error and per rad/s of yaw-rate error
HEADING_GAIN, YAW_RATE_GAIN_S = 1.0, 0.3


@dataclass(frozen=True)
class Manoeuvre:
    """From ``t_c`` on: the brake pedal held at ``brake_pct``; with ``wheel_offset_rad`` (positive: to the
    left) not 0, an evasive lane change of that wheel offset (module docstring)."""

    brake_pct: float
    wheel_offset_rad: float

    def pulse_s(self, speed_mps: float) -> float:
        """The length ``T`` of each half of the double pulse at ``speed_mps``."""
        delta = abs(self.wheel_offset_rad) / STEERING_RATIO
        if delta == 0.0:
            return math.inf  # braking straight: no pulse
        return math.sqrt(LANE_WIDTH_M * WHEELBASE_M / (max(speed_mps, 1.0) ** 2 * delta))


def _grid() -> tuple[Manoeuvre, ...]:
    offsets = [s * math.radians(d) for d in WHEEL_OFFSETS_DEG for s in (1.0, -1.0)]
    return (Manoeuvre(100.0, 0.0),) + tuple(Manoeuvre(b, o) for b in BRAKE_LEVELS_PCT for o in offsets)


#: every manoeuvre, in the order tried (braking straight, then 3 brake levels x 12 lane changes)
GRID = _grid()


@dataclass(frozen=True)
class OracleVerdict:
    """The oracle's answer for one cell."""

    cell_id: str
    #: the object touched with no intervention (None: no contact, nothing to avoid)
    hit_object: str | None
    #: when the radar had confirmed it (None: never confirmed before the contact)
    confirmed_at_s: float | None
    #: the first manoeuvre of the grid that avoids (None: none does, or nothing to avoid)
    avoided_by: Manoeuvre | None
    tried: int

    @property
    def avoidable(self) -> bool:
        """Contact could be avoided: there was none, or a manoeuvre of the grid avoids it."""
        return self.hit_object is None or self.avoided_by is not None


def _avoided(outcome: Outcome) -> bool:
    return outcome.error is None and not outcome.collided and (
        outcome.planar is None or outcome.planar.road_departure_m == 0.0)


def _ignore(_msg, _t_s: float) -> bool:
    return False


def _run(data: Mapping[str, Any], fmu: Path, adjust: Callable[[ClosedLoop], None] | None = None) -> Outcome:
    """One closed loop with the ECU disconnected: the actuator gateway is offered none of its frames, so the
    plant gets the driver's pedals and wheel alone (the ECU still runs, unheard)."""
    scenario = scenario_from_dict(data)
    loop = ClosedLoop(scenario, fmu, "none")
    loop.gateway.offer = loop.steering_gateway.offer = _ignore
    if adjust is not None:
        adjust(loop)
    return outcome_of(loop.run(), scenario)


def _watch_reports(index: int, confirm_reports: int, seen: list[float]) -> Callable[[ClosedLoop], None]:
    """Wraps the loop's 2-D radar feed: appends to ``seen`` the time of the ``confirm_reports``-th consecutive
    report of object ``index`` (once)."""

    def adjust(loop: ClosedLoop) -> None:
        feed, streak = loop.tracks.step, [0]

        def step(cycle: int, t_s: float, ego):
            tracks = feed(cycle, t_s, ego)
            if tracks is not None and not seen:
                streak[0] = streak[0] + 1 if any(t.id == index for t in tracks) else 0
                if streak[0] >= confirm_reports:
                    seen.append(t_s)
            return tracks

        loop.tracks.step = step

    return adjust


def _apply(manoeuvre: Manoeuvre, t_c: float) -> Callable[[ClosedLoop], None]:
    """Replaces the loop's driver and wheel by ``manoeuvre`` from ``t_c`` on."""

    def adjust(loop: ClosedLoop) -> None:
        driver, steering = loop.driver, loop.steering
        pedals = Pedals(0.0, manoeuvre.brake_pct)
        state: dict[str, float] = {"wheel_rad": 0.0}

        def drive(t_s: float, position_m: float, speed_mps: float) -> Pedals:
            return pedals if t_s >= t_c else driver(t_s, position_m, speed_mps)

        def steer(t_s: float, ego) -> float:
            if t_s < t_c:
                state["wheel_rad"] = 0.0 if steering is None else steering(t_s, ego)
                return state["wheel_rad"]
            if "pulse_s" not in state:  # at t_c: the pulse's length, the heading and yaw rate to hold after it
                state.update(pulse_s=manoeuvre.pulse_s(ego.speed_mps), yaw_rad=ego.yaw_rad,
                             yaw_rate_radps=ego.yaw_rate_radps)
            return state["wheel_rad"] + _evasion_rad(manoeuvre, t_s - t_c, ego, state)

        loop.driver, loop.steering = drive, steer

    return adjust


def _evasion_rad(manoeuvre: Manoeuvre, since_s: float, ego, state: Mapping[str, float]) -> float:
    """The wheel's offset ``since_s`` after ``t_c``: the double pulse, then holding the course of ``t_c`` (the
    heading it had, turning on at the yaw rate it had: a proportional law on the heading and yaw-rate errors)."""
    if manoeuvre.wheel_offset_rad == 0.0:
        return 0.0
    phase = since_s / state["pulse_s"]
    if phase < 2.0:
        return manoeuvre.wheel_offset_rad if phase < 1.0 else -manoeuvre.wheel_offset_rad
    heading_error = ego.yaw_rad - state["yaw_rad"] - state["yaw_rate_radps"] * since_s
    rate_error = ego.yaw_rate_radps - state["yaw_rate_radps"]
    return -STEERING_RATIO * (HEADING_GAIN * heading_error + YAW_RATE_GAIN_S * rate_error)


def judge(cell_id: str, data: Mapping[str, Any], fmu: Path, confirm_reports: int = 3) -> OracleVerdict:
    """The oracle's verdict for one planar cell's scenario mapping (module docstring)."""
    base = _run(data, fmu)
    if _avoided(base) or base.planar is None or base.planar.hit_object is None:
        return OracleVerdict(cell_id, None, None, None, 0)
    names = [o.get("name", f"object {i}") for i, o in enumerate(data.get("objects", []))]
    index = names.index(base.planar.hit_object) if base.planar.hit_object in names else -1
    seen: list[float] = []
    _run(data, fmu, _watch_reports(index, confirm_reports, seen))
    if not seen:
        return OracleVerdict(cell_id, base.planar.hit_object, None, None, 0)
    for n, manoeuvre in enumerate(GRID, 1):
        if _avoided(_run(data, fmu, _apply(manoeuvre, seen[0]))):
            return OracleVerdict(cell_id, base.planar.hit_object, seen[0], manoeuvre, n)
    return OracleVerdict(cell_id, base.planar.hit_object, seen[0], None, len(GRID))


def _describe(v: OracleVerdict) -> str:
    if v.hit_object is None:
        return "no contact without an ECU"
    if v.confirmed_at_s is None:
        return f"hits {v.hit_object}; never confirmed before the contact"
    if v.avoided_by is None:
        return f"hits {v.hit_object}; confirmed at {v.confirmed_at_s:.2f} s; no manoeuvre of the grid avoids ({v.tried} tried)"
    m = v.avoided_by
    how = "braking straight" if m.wheel_offset_rad == 0.0 else (
        f"a lane change to the {'left' if m.wheel_offset_rad > 0 else 'right'} "
        f"({abs(math.degrees(m.wheel_offset_rad)):.0f} deg at the wheel)")
    return f"hits {v.hit_object}; confirmed at {v.confirmed_at_s:.2f} s; avoided by {how}, brake {m.brake_pct:.0f} %"


def main(argv: list[str] | None = None) -> int:
    """``python -m cosim.matrix.oracle CATALOGUE [--cell ID ...] [--json FILE]``: the verdict of every planar cell."""
    import argparse
    import json
    import logging
    from dataclasses import asdict

    from ..loop.experiment import resolve_fmu
    from .catalogue import load_catalogue

    ap = argparse.ArgumentParser(prog="python -m cosim.matrix.oracle", description=__doc__.splitlines()[0])
    ap.add_argument("catalogue", help="catalogue TOML file or bundled name (its planar cells are judged)")
    ap.add_argument("--cell", action="append", default=[], help="judge only this cell id (repeatable)")
    ap.add_argument("--json", help="also write the verdicts to this JSON file")
    args = ap.parse_args(argv)
    logging.getLogger("cosim").setLevel(logging.ERROR)  # the disconnected ECU's gateway warns every run
    cat = load_catalogue(args.catalogue)
    cells = [c for c in cat.cells if c.params.get("scene") is not None and (not args.cell or c.cell_id in args.cell)]
    verdicts = []
    for n, cell in enumerate(cells, 1):
        data = cell.scenario_dict()
        verdicts.append(judge(cell.cell_id, data, resolve_fmu(scenario_from_dict(data))))
        print(f"[{n:4d}/{len(cells)}] {cell.cell_id}: {_describe(verdicts[-1])}", flush=True)
    unavoidable = [v.cell_id for v in verdicts if not v.avoidable]
    print(f"{len(cells) - len(unavoidable)} of {len(cells)} cells avoidable; none of the grid avoids in: "
          f"{', '.join(unavoidable) or '-'}")
    if args.json:
        Path(args.json).write_text(json.dumps([asdict(v) for v in verdicts], indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
