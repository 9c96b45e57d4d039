"""Print what today's ECU (``tightening``) does in each bundled planar scenario, as a Markdown table.

Run: ``python docgen/planar_outcomes.py``. ``docs/plane.md`` shows its output in a generated block
(``python -m docgen``), so the table cannot drift from the runs. Each row is one
:class:`cosim.loop.master.ClosedLoop` run with the ECU in process, as ``crd run NAME`` runs it:
contact and impact speed, the lowest speed after the first second (a brake shows as a dip), the
contingency invocations and the largest lateral offset of the ego's reference point.
"""

from __future__ import annotations

from cosim.cli.scenarios import find_scenario
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import ClosedLoop
from cosim.scenarios.loader import load_scenario

SCENARIOS = ("lane_change_parked_car", "curve_parked_car", "crossing_pedestrian", "paper_cyclist_road")
STRATEGY = "tightening"


def row(name: str) -> str:
    """One table row: the run of the bundled scenario ``name`` with :data:`STRATEGY`."""
    scenario = load_scenario(find_scenario(name))
    record = ClosedLoop(scenario, resolve_fmu(scenario), STRATEGY).run()
    if record.error:
        raise SystemExit(f"{name}: {record.error}")
    m, columns = record.metrics, record.columns
    t, v, y = (columns.index(c) for c in ("time_s", "speed_mps", "y_m"))
    later = [r[v] for r in record.rows if r[t] >= 1.0] or [m.max_speed_mps]
    contact = f"yes, {m.impact_speed_mps:.2f} m/s" if m.collided else "no"
    return (f"| `{name}` | {contact} | {min(later):.2f} | {m.max_speed_mps:.2f} | {m.contingency_invocations} "
            f"| {max(abs(r[y]) for r in record.rows):.2f} |")


def main() -> None:
    print("| scenario | contact | lowest speed after 1 s (m/s) | top speed (m/s) | contingencies | largest \\|y\\| (m) |")
    print("|---|---|---|---|---|---|")
    for name in SCENARIOS:
        print(row(name))


if __name__ == "__main__":
    main()
