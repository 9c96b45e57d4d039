"""``report.md`` of a fleet run: the dance figures per vehicle and for the scene, and the plot."""

from __future__ import annotations

from pathlib import Path

from .config import Fleet
from .dance_metrics import SceneDance


def _fmt(x: float | None, spec: str = ".2f") -> str:
    return "-" if x is None else format(x, spec)


def dance_table(dance: SceneDance) -> str:
    """The per-vehicle table (markdown)."""
    lines = ["| vehicle | strategy | contingencies | decelerations | recoveries (m/s) | collided | impact (m/s) "
             "| cleared at (s) |", "|---|---|---:|---:|---|---|---:|---:|"]
    for v in dance.vehicles:
        rec = ", ".join(f"{x:.2f}" for x in v.recoveries_mps) or "-"
        lines.append(f"| {v.name} | {v.strategy} | {v.contingency_invocations} | {v.decelerations} | {rec} | "
                     f"{'yes' if v.collided else 'no'} | {_fmt(v.impact_speed_mps)} | {_fmt(v.cleared_at_s)} |")
    return "\n".join(lines)


def scene_line(dance: SceneDance) -> str:
    return (f"first intervention {_fmt(dance.first_intervention_s)} s, first contingency "
            f"{_fmt(dance.first_contingency_s)} s, time in deadlock {dance.deadlock_s:.2f} s, all cleared "
            f"{_fmt(dance.all_cleared_s)} s, time to clear {_fmt(dance.time_to_clear_s)} s, collisions "
            f"{dance.collisions}")


def write_fleet_report(path: Path, fleet: Fleet, dance: SceneDance) -> None:
    lines = [f"# crd fleet: {fleet.fleet.name}", "", dance_table(dance), "", f"Scene: {scene_line(dance)}.", "",
             "![speeds](speeds.png)", ""]
    path.write_text("\n".join(lines))
