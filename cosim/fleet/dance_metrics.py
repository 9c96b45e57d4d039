"""The reciprocal dance between vehicles, judged from the time series (issue 23, item 4).

Per vehicle, from its record:

* **contingency invocations**: its gateway's count (``metrics.contingency_invocations``);
* **separate decelerations**: the zigzag detector of the one-car study
  (:func:`cosim.results.speed_dance.speed_dance`, 0.5 m/s down and up) on its logged speed;
* **collision** and the relative impact speed;
* **cleared at**: the first time its box centre has left the conflict zone (``[fleet] conflict_radius_m``
  around ``conflict_x_m``, ``conflict_y_m``) after having been in it, or having passed the centre at
  more than that radius while moving away from it. None: it never cleared.

For the scene, from the world rows (one per ECU cycle):

* **time in deadlock**: the cycles in which every vehicle not yet cleared is within
  ``approach_radius_m`` of the centre, and none of them moves faster than ``progress_speed_mps``
  (at least one not cleared): nobody goes, nobody gives way;
* **first contingency**, **first intervention**: the earliest time any car's ECU was in CONTINGENCY
  (its ``ecu_mode`` column), or in TIGHTENING or CONTINGENCY;
* **all cleared**: when the last vehicle cleared (None: not every vehicle cleared);
* **time to clear**: from the first contingency (the issue's measure; without one, from the first
  intervention) to all cleared (None: not every vehicle cleared, or no ECU intervened).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Sequence

from ..results.run_record import RunRecord
from ..results.speed_dance import speed_dance
from .config import FleetSection

CONTINGENCY, TIGHTENING = "CONTINGENCY", "TIGHTENING"


@dataclass(frozen=True)
class VehicleDance:
    """One vehicle's dance figures."""

    name: str
    strategy: str
    contingency_invocations: int
    decelerations: int
    recoveries_mps: tuple[float, ...]
    collided: bool
    impact_speed_mps: float | None
    cleared_at_s: float | None


@dataclass(frozen=True)
class SceneDance:
    """The scene's dance figures (module docstring) and each vehicle's."""

    vehicles: tuple[VehicleDance, ...]
    deadlock_s: float
    first_contingency_s: float | None
    first_intervention_s: float | None
    all_cleared_s: float | None
    time_to_clear_s: float | None
    collisions: int

    def as_dict(self) -> dict:
        return asdict(self)


def _cleared_at(xs: Sequence[float], ys: Sequence[float], ts: Sequence[float], zone: FleetSection) -> float | None:
    """When a path of box centres has left the conflict zone after entering it, or passed outside it moving away."""
    r, cx, cy = zone.conflict_radius_m, zone.conflict_x_m, zone.conflict_y_m
    entered, closest = False, math.inf
    for x, y, t in zip(xs, ys, ts):
        d = math.hypot(x - cx, y - cy)
        if d <= r:
            entered = True
        elif entered or (d > closest + 0.5 and closest < 2.0 * r):
            return t
        closest = min(closest, d)
    return None


def _first_in(record: RunRecord, modes: tuple[str, ...]) -> float | None:
    mode = record.columns.index("ecu_mode")
    return next((row[0] for row in record.rows if row[mode] in modes), None)


def _earliest(times: Sequence[float | None]) -> float | None:
    known = [t for t in times if t is not None]
    return min(known) if known else None


def vehicle_dance(name: str, record: RunRecord, world: Sequence[tuple[float, ...]], index: int,
                  zone: FleetSection) -> VehicleDance:
    """Vehicle ``index``'s figures: its record, and its columns of the world rows."""
    speed = record.columns.index("speed_mps")
    dance = speed_dance(row[speed] for row in record.rows)
    ts = [w[0] for w in world]
    xs, ys = [w[1 + 4 * index] for w in world], [w[2 + 4 * index] for w in world]
    m = record.metrics
    return VehicleDance(name, record.strategy, m.contingency_invocations, dance.decelerations,
                        tuple(round(v, 3) for v in dance.rises_mps), m.collided,
                        m.impact_speed_mps if m.collided else None, _cleared_at(xs, ys, ts, zone))


def _deadlock_s(world: Sequence[tuple[float, ...]], cleared: Sequence[float | None], zone: FleetSection) -> float:
    if len(world) < 2:
        return 0.0
    dt = world[1][0] - world[0][0]
    total = 0.0
    for w in world:
        t, waiting = w[0], []
        for i, done in enumerate(cleared):
            if done is None or t < done:
                x, y, v = w[1 + 4 * i], w[2 + 4 * i], w[4 + 4 * i]
                waiting.append((math.hypot(x - zone.conflict_x_m, y - zone.conflict_y_m), v))
        if waiting and all(d <= zone.approach_radius_m and v < zone.progress_speed_mps for d, v in waiting):
            total += dt
    return total


def scene_dance(names: Sequence[str], records: Sequence[RunRecord], world: Sequence[tuple[float, ...]],
                zone: FleetSection) -> SceneDance:
    """Every figure of the module docstring."""
    vehicles = tuple(vehicle_dance(n, r, world, i, zone) for i, (n, r) in enumerate(zip(names, records)))
    first = _earliest([_first_in(r, (CONTINGENCY,)) for r in records])
    intervened = _earliest([_first_in(r, (CONTINGENCY, TIGHTENING)) for r in records])
    cleared = [v.cleared_at_s for v in vehicles]
    last = max(cleared) if cleared and all(c is not None for c in cleared) else None
    start = first if first is not None else intervened
    to_clear = None if start is None or last is None else max(0.0, last - start)
    return SceneDance(vehicles, round(_deadlock_s(world, cleared, zone), 6), first, intervened, last, to_clear,
                      sum(v.collided for v in vehicles))
