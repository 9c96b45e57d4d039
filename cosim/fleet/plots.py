"""The fleet's figures: every vehicle's speed against time (its contingencies shaded) and the paths seen
from above."""

from __future__ import annotations

from pathlib import Path

from .config import Fleet
from .dance_metrics import CONTINGENCY
from .lockstep import FleetRecord


def _spans(times: list[float], flags: list[bool]) -> list[tuple[float, float]]:
    """The time spans over which ``flags`` holds (each from its first sample to the next sample after it)."""
    spans, start = [], None
    for i, (t, f) in enumerate(zip(times, flags)):
        if f and start is None:
            start = t
        if not f and start is not None:
            spans.append((start, t))
            start = None
    if start is not None:
        spans.append((start, times[-1]))
    return spans


def speeds_plot(path: Path, fleet: Fleet, record: FleetRecord) -> None:
    """``speeds.png``: one panel per vehicle (shared time axis), CONTINGENCY shaded; paths from above beside."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = len(fleet.vehicles)
    fig = plt.figure(figsize=(12, 1.6 + 1.5 * n))
    grid = fig.add_gridspec(n, 2, width_ratios=(2.2, 1.0))
    first = None
    for i, (name, r) in enumerate(zip(fleet.names, record.records)):
        ax = fig.add_subplot(grid[i, 0], sharex=first)
        first = first or ax
        t = [row[0] for row in r.rows]
        v = [row[r.columns.index("speed_mps")] for row in r.rows]
        mode = r.columns.index("ecu_mode")
        for a, b in _spans(t, [row[mode] == CONTINGENCY for row in r.rows]):
            ax.axvspan(a, b, color="tab:red", alpha=0.15, lw=0)
        ax.plot(t, v, color=f"C{i}", lw=1.4)
        ax.set_ylabel(f"{name}\nm/s")
        ax.set_title(f"{name} ({r.strategy}): {r.metrics.contingency_invocations} contingencies"
                     + (f", hit at {r.metrics.impact_speed_mps:.2f} m/s" if r.metrics.collided else ""), fontsize=9)
        ax.grid(alpha=0.3)
    first.figure.axes[-1].set_xlabel("time (s)")
    _paths_panel(fig.add_subplot(grid[:, 1]), fleet, record, plt)
    fig.suptitle(f"{fleet.fleet.name}: speed of every car (red: its ECU in CONTINGENCY)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _paths_panel(top, fleet: Fleet, record: FleetRecord, plt) -> None:
    """Every car's path in the world frame (a dot at its end), the conflict zone, the world objects."""
    for i, name in enumerate(fleet.names):
        xs = [w[1 + 4 * i] for w in record.world_rows]
        ys = [w[2 + 4 * i] for w in record.world_rows]
        top.plot(xs, ys, color=f"C{i}", lw=1.2, label=name)
        if xs:
            top.plot(xs[-1], ys[-1], "o", color=f"C{i}")
    z = fleet.fleet
    top.add_patch(plt.Circle((z.conflict_x_m, z.conflict_y_m), z.conflict_radius_m, fill=False, ls="--", color="0.5"))
    for obj in fleet.objects:
        top.plot(obj.pose.x_m, obj.pose.y_m, "s", color="0.3", ms=6)
    top.set_aspect("equal", adjustable="datalim")
    top.set_title("paths from above (world frame; dot: end)", fontsize=9)
    top.legend(fontsize=8)
    top.grid(alpha=0.3)
