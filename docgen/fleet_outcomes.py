"""Print what the bundled fleet scenes give, per strategy and way-out rule, as a Markdown table.

Run: ``python docgen/fleet_outcomes.py``. ``docs/fleet.md`` shows its output in a generated block
(``python -m docgen``), so the table cannot drift from the runs. Each row is one
:func:`cosim.fleet.output.run_fleet` run with every ECU in process, as ``crd fleet NAME --strategy S
--way-out W`` runs it (no files): contacts, the fewest separate decelerations of any car and the smallest
recovery between them, the time in deadlock, and the time from the first contingency (without one, the
first intervention) until every car has cleared the conflict zone.
"""

from __future__ import annotations

from cosim.cli.fleet import bundled_scenes, find_scene
from cosim.fleet.config import load_fleet
from cosim.fleet.output import run_fleet

RUNS = (("none", "none"), ("tightening", "none"), ("tightening", "right_of_way"), ("tightening", "reciprocal"))


def _fmt(x: float | None) -> str:
    return "-" if x is None else f"{x:.2f}"


#: mixed populations: (scene, each car's strategy), way-out rule none
MIXED = (("crossing", {"west": "tightening", "south": "none"}),)


def row(path, strategy: str | dict[str, str], way_out: str) -> str:
    """One table row: the scene at ``path`` with every car's strategy (or each car's) and way-out rule."""
    fleet = load_fleet(path, way_out)
    strategies = strategy if isinstance(strategy, dict) else {name: strategy for name in fleet.names}
    record, d = run_fleet(fleet, None, strategies)
    errors = [r.error for r in record.records if r.error]
    if errors:
        raise SystemExit(f"{path.stem}: {errors[0]}")
    decs = min(v.decelerations for v in d.vehicles)
    rec = min((min(v.recoveries_mps) for v in d.vehicles if v.recoveries_mps), default=None)
    hits = f"{d.collisions} ({max(v.impact_speed_mps or 0.0 for v in d.vehicles):.2f} m/s)" if d.collisions else "0"
    shown = strategy if isinstance(strategy, str) else ", ".join(f"{k} {v}" for k, v in strategy.items())
    return (f"| `{path.stem}` | {len(fleet.vehicles)} | {shown} | {way_out} | {hits} | {decs} | {_fmt(rec)} | "
            f"{d.deadlock_s:.2f} | {_fmt(d.time_to_clear_s) if d.all_cleared_s is not None else 'not cleared'} |")


def main() -> None:
    print("| scene | cars | strategy | way out | contacts (top impact) | fewest decelerations | smallest recovery "
          "(m/s) | deadlock (s) | time to clear (s) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for path in bundled_scenes():
        for strategy, way_out in RUNS:
            print(row(path, strategy, way_out))
    for name, strategies in MIXED:
        print(row(find_scene(name), strategies, "none"))


if __name__ == "__main__":
    main()
