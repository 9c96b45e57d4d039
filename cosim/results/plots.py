"""PNG plots with matplotlib's Agg backend (no display needed).

* ``speed_profiles.png``: the paper's figure — speed against position, one
  line per strategy, the object's position marked;
* ``<strategy>/timeline.png``: speed, gap, applied throttle/brake and ECU mode over time.
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

from can_dbc import MODE_NAMES

from .run_record import RunRecord

_MODE_LEVEL = {name: value for value, name in MODE_NAMES.items()} | {"NO_OVERRIDE": -1}


def _pyplot():
    """matplotlib's pyplot on the Agg backend, imported on the first plot (it costs about 0.3 s)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def speed_profiles(path: Path, records: Iterable[RunRecord], object_position_m: float | None) -> None:
    """Speed (m/s) against position (m), one line per strategy (Johnson 2019, Fig. 2)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=110)
    for r in records:
        label = r.strategy + (" (collided)" if r.metrics.collided else "")
        ax.plot(r.column("position_m"), r.column("speed_mps"), label=label, linewidth=1.2)
    if object_position_m is not None:
        ax.axvline(object_position_m, color="k", linestyle="--", linewidth=1)
        ax.annotate("cyclist", (object_position_m, 0), xytext=(-50, 10), textcoords="offset points")
    ax.set_xlabel("position (m)")
    ax.set_ylabel("speed (m/s)")
    ax.set_title("Vehicle speed as a function of path position")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def timeline(path: Path, record: RunRecord) -> None:
    """Speed, gap, pedals/commands and ECU mode against time for one run."""
    plt = _pyplot()
    t = record.column("time_s")
    fig, axes = plt.subplots(4, 1, figsize=(8, 8), dpi=100, sharex=True)
    axes[0].plot(t, record.column("speed_mps"))
    axes[0].set_ylabel("speed (m/s)")
    gaps = [g if g < 1e9 else float("nan") for g in record.column("gap_m")]
    axes[1].plot(t, gaps)
    axes[1].set_ylabel("gap (m)")
    axes[2].plot(t, record.column("throttle"), label="throttle")
    axes[2].plot(t, record.column("brake"), label="brake")
    axes[2].plot(t, [p / 100 for p in record.column("accel_pedal_pct")], ":", label="accel pedal")
    axes[2].set_ylabel("command (0..1)")
    axes[2].legend(loc="upper right")
    axes[3].step(t, [_MODE_LEVEL.get(m, -2) for m in record.column("ecu_mode")], where="post")
    axes[3].set_yticks(list(_MODE_LEVEL.values()), list(_MODE_LEVEL))
    axes[3].set_xlabel("time (s)")
    axes[0].set_title(f"{record.strategy}")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
