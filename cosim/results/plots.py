"""PNG plots with matplotlib's Agg backend (no display needed), imported only when plotting.

* ``speed_profiles.png``: the paper's figure — speed against position, one
  line per strategy, the object marked with its scenario name, each contingency
  invocation (the ECU's mode entering CONTINGENCY) marked on its line, a
  collision marked where one happened — over the whole path and, below, zoomed
  on the last 75 m before the object, where the strategies differ (claim 4's
  split at 200 m marked);
* ``<strategy>/timeline.png``: speed, gap (a symmetric-log axis, so the last
  metres show beside the first 200: the final gap is also written out),
  deceleration, the driver's pedals under the applied throttle/brake, and the
  ECU mode over time, with the start-up (FAULT until the inputs are valid)
  labelled, trimmed to the active part of the run (the rest is stated, not
  drawn) with the collision marked;
* :func:`overlay_profiles`: two runs' speed profiles on one figure (``crd compare``).

Legends sit outside the axes, so they cover no data, and the figure widens when
one would run off its right edge (:func:`fit_legends`).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from .run_record import TIMESERIES_COLUMNS, RunRecord

STRATEGY_COLORS = {"none": "C0", "conservative": "C1", "tightening": "C2", "adaptive": "C4"}  # in every plot
ZOOM_SPAN_M = 75.0  # the zoomed panel: this far before the object (150..225 m in the paper)
_COLLISION = dict(color="crimson", marker="X", markersize=10, linestyle="none", zorder=5)
# Fixed margins (fractions of the figure) leave the right-hand strip to the legends; a layout
# engine would find them too, at about half of the plotting time.
_RIGHT = 0.75
_POSITION, _SPEED, _MODE = (TIMESERIES_COLUMNS.index(c) for c in ("position_m", "speed_mps", "ecu_mode"))
#: gap axis ticks (m): a symmetric-log axis (linear below 1 m) shows both 200 m and the last metres
_GAP_TICKS_M = (0, 1, 3, 10, 30, 100, 300, 1000)


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def mode_levels() -> dict[str, int]:
    """ECU mode name -> its level in a timeline's mode panel: the DBC's ``VAL_`` of the mode, NO_OVERRIDE -1."""
    from can_dbc import MODE_NAMES  # here, not above: a plot worker would hold can_dbc's 14 MB for this table

    return {name: value for value, name in MODE_NAMES.items()} | {"NO_OVERRIDE": -1}


def preload_matplotlib() -> None:
    """Import matplotlib now (0.4 s), e.g. while runs go in worker processes (:mod:`cosim.loop.concurrent`)."""
    _pyplot()


@dataclass(frozen=True)
class Collision:
    """Where and when a run hit the object: time (s), position (m), speed (m/s)."""

    t_s: float
    position_m: float
    speed_mps: float


def collision_point(record: RunRecord) -> Collision | None:
    """The collision, extrapolated from the last 10 ms sample to the collision event's time."""
    t_c = next((e.t_s for e in record.events if e.kind == "collision"), None)
    if t_c is None or not record.rows:
        return None
    t, x, v, a = (record.rows[-1][i] for i in range(4))
    dt = max(0.0, t_c - t)
    return Collision(t_c, x + v * dt + 0.5 * a * dt * dt, max(0.0, v + a * dt))


@dataclass(frozen=True)
class Profile:
    """One line of a speed-profile plot."""

    label: str
    record: RunRecord
    linestyle: str = "-"
    color: str | None = None


def contingency_onsets(record: RunRecord) -> list[tuple[float, float]]:
    """(position (m), speed (m/s)) of each sample where the ECU's mode became CONTINGENCY: the
    contingency invocations, the transitions :mod:`cosim.world.gateway` counts."""
    onsets, before = [], None
    for row in record.rows:
        mode = row[_MODE]
        if mode == "CONTINGENCY" and before != "CONTINGENCY":
            onsets.append((row[_POSITION], row[_SPEED]))
        before = mode
    return onsets


def _draw_profiles(ax, profiles: Sequence[Profile], object_position_m: float | None, object_name: str) -> None:
    for p in profiles:
        color = p.color or STRATEGY_COLORS.get(p.record.strategy)
        ax.plot(p.record.column("position_m"), p.record.column("speed_mps"), p.linestyle, color=color,
                label=p.label, linewidth=1.3)
        onsets = contingency_onsets(p.record)
        if onsets:
            ax.plot(*zip(*onsets), marker="v", markersize=6, linestyle="none", color=color, markeredgecolor="k",
                    markeredgewidth=0.5, zorder=4, label=f"{p.label}: ECU intervened (contingency) ×{len(onsets)}")
        hit = collision_point(p.record)
        if hit is not None:
            ax.plot([hit.position_m], [hit.speed_mps], **_COLLISION,
                    label=f"{p.label}: collision at {hit.speed_mps:.2f} m/s")
    if object_position_m is not None:
        ax.axvline(object_position_m, color="k", linestyle="--", linewidth=1,
                   label=f"{object_name} at {object_position_m:g} m")
    ax.set_ylabel("speed (m/s)")
    ax.set_xlabel("position (m)")
    _ticks(6, ax.yaxis)
    ax.grid(True, alpha=0.3)


def _zoom(ax, profiles: Sequence[Profile], lo_m: float, hi_m: float) -> None:
    speeds = [v for p in profiles for x, v in zip(p.record.column("position_m"), p.record.column("speed_mps"))
              if lo_m <= x <= hi_m]
    ax.set_xlim(lo_m, hi_m)
    if speeds:
        ax.set_ylim(-0.5, max(speeds) * 1.05 + 0.5)


# zlib level 1 instead of Pillow's default 6: a PNG 10-20 % larger, 10 ms less per figure (of 0.15 s)
_PNG_OPTIONS = {"compress_level": 1}


def _save(fig, path: Path) -> None:
    fig.savefig(path, pil_kwargs=_PNG_OPTIONS)
    _pyplot().close(fig)


def _ticks(nbins: int, *axes) -> None:
    """At most ``nbins`` intervals on each axis, on the default locator's round steps (which allows up to
    9): each tick is a few artists built and drawn at every save, so fewer cost less (the timeline: 25 ms
    of 0.15 s)."""
    from matplotlib.ticker import MaxNLocator

    for axis in axes:
        axis.set_major_locator(MaxNLocator(nbins=nbins, steps=[1, 2, 2.5, 5, 10]))


def fit_legends(fig) -> None:
    """Widen ``fig`` when a legend runs off its right edge; the axes keep their size in inches.

    A figure legend is anchored in figure fractions, so its anchor is moved with the axes.
    """
    renderer = fig.canvas.get_renderer()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    if not legends:
        return
    over_in = max(leg.get_window_extent(renderer).x1 for leg in legends) / fig.dpi - fig.get_figwidth() + 0.1
    if over_in <= 0.0:
        return
    scale = fig.get_figwidth() / (fig.get_figwidth() + over_in)
    fig.set_figwidth(fig.get_figwidth() + over_in)
    for ax in fig.axes:
        box = ax.get_position()
        ax.set_position([box.x0 * scale, box.y0, box.width * scale, box.height])
    for legend in fig.legends:
        anchor = legend.get_bbox_to_anchor().transformed(fig.transFigure.inverted())
        legend.set_bbox_to_anchor((anchor.x0 * scale, anchor.y0), transform=fig.transFigure)


def profile_figure(profiles: Sequence[Profile], object_position_m: float | None,
                   title: str, split_m: float | None = None, object_name: str = "object"):
    """Speed against position; with an object (named ``object_name`` in the legend), a second panel
    zoomed on the last ``ZOOM_SPAN_M`` before it."""
    plt = _pyplot()
    zoom = object_position_m is not None
    fig, axes = plt.subplots(2 if zoom else 1, 1, figsize=(10.5, 7.5 if zoom else 4.5), dpi=110, squeeze=False)
    top = 0.95 if zoom else 0.91
    fig.subplots_adjust(left=0.07, right=_RIGHT, top=top, bottom=0.08 if zoom else 0.12, hspace=0.3)
    full = axes[0][0]
    _draw_profiles(full, profiles, object_position_m, object_name)
    full.set_title(title)
    if zoom:
        near = axes[1][0]
        _draw_profiles(near, profiles, object_position_m, object_name)
        lo = max(0.0, object_position_m - ZOOM_SPAN_M)
        _zoom(near, profiles, lo, object_position_m + 2.0)
        full.axvspan(lo, object_position_m + 2.0, color="0.85", alpha=0.4, label="zoomed below")
        if split_m is not None and lo < split_m < object_position_m:
            near.axvline(split_m, color="0.4", linestyle=":", linewidth=1.2, label=f"claim 4 split ({split_m:g} m)")
        near.set_title(f"zoom: {lo:g}–{object_position_m + 2.0:g} m")
    entries = {}  # one legend entry per label, over both panels
    for ax in fig.axes:
        entries.update({lab: h for h, lab in zip(*ax.get_legend_handles_labels()) if lab not in entries})
    fig.legend(list(entries.values()), list(entries), loc="upper left", bbox_to_anchor=(_RIGHT + 0.01, top),
               fontsize=9, borderaxespad=0.0)
    fit_legends(fig)
    return fig


def speed_profiles(path: Path, records: Sequence[RunRecord], object_position_m: float | None,
                   split_m: float | None = None, object_name: str = "object") -> None:
    """Speed (m/s) against position (m), one line per strategy (Johnson 2019, Fig. 2)."""
    profiles = [Profile(r.strategy, r) for r in records]
    _save(profile_figure(profiles, object_position_m, "Vehicle speed as a function of path position", split_m,
                         object_name), path)


def overlay_profiles(path: Path, runs: Sequence[tuple[str, Sequence[RunRecord]]],
                     object_position_m: float | None, title: str, object_name: str = "object") -> None:
    """Two (or more) runs' speed profiles: one colour per strategy, one line style per run."""
    styles = ("-", "--", ":", "-.")
    profiles = [Profile(f"{name}: {r.strategy}", r, styles[i % len(styles)])
                for i, (name, records) in enumerate(runs) for r in records]
    _save(profile_figure(profiles, object_position_m, title, object_name=object_name), path)



def active_end_s(record: RunRecord) -> float:
    """Time (s) of the last sample that differs from the final one (speed or gap by >= 0.01, a command, the mode)."""
    rows = record.rows
    if not rows:
        return 0.0
    last = rows[-1]
    for row in reversed(rows):
        t, _, v, _, throttle, brake, mode, gap, acc, brk = row[:10]
        if (abs(v - last[2]) >= 0.01 or abs(gap - last[7]) >= 0.01 or mode != last[6]
                or (throttle, brake, acc, brk) != (last[4], last[5], last[8], last[9])):
            return t
    return rows[0][0]


def timeline(path: Path, record: RunRecord, levels: dict[str, int] | None = None) -> None:
    """``timeline.png`` of one run (:func:`timeline_figure`)."""
    _save(timeline_figure(record, levels), path)


def timeline_figure(record: RunRecord, levels: dict[str, int] | None = None):
    """Speed, gap, deceleration, pedals/commands and ECU mode against time for one run, trimmed to its
    active part (``levels``: :func:`mode_levels`, read here when not given)."""
    plt = _pyplot()
    levels = mode_levels() if levels is None else levels
    t = record.column("time_s")
    end_s = t[-1] if t else 0.0
    shown_s = min(end_s, active_end_s(record) + 2.0)
    fig, axes = plt.subplots(5, 1, figsize=(10, 9.6), dpi=100, sharex=True)
    fig.subplots_adjust(left=0.13, right=_RIGHT, top=0.96, bottom=0.06, hspace=0.12)
    axes[0].plot(t, record.column("speed_mps"), label="speed")
    axes[0].set_ylabel("speed (m/s)")
    _gap_panel(axes[1], t, record)
    axes[2].plot(t, [-a for a in record.column("accel_mps2")], color="C3", label="deceleration")
    axes[2].set_ylabel("deceleration\n(m/s², braking > 0)")
    _command_panel(axes[3], t, record)
    axes[4].step(t, [levels.get(m, -2) for m in record.column("ecu_mode")], where="post", label="ECU mode")
    axes[4].set_yticks(list(levels.values()), list(levels))
    _ticks(4, *(ax.yaxis for ax in (axes[0], axes[2], axes[3])))
    _ticks(6, axes[-1].xaxis)  # shared by the panels
    _label_startup(axes, t, record.column("ecu_mode"), levels)
    hit = collision_point(record)
    if hit is not None:
        for ax in axes:
            ax.axvline(hit.t_s, color="crimson", linewidth=1.2, linestyle="--")
        axes[0].plot([hit.t_s], [hit.speed_mps], **_COLLISION,
                     label=f"collision at {hit.t_s:.2f} s, {hit.speed_mps:.2f} m/s")
    axes[0].set_title(record.strategy)
    axes[-1].set_xlim(0.0, max(shown_s, 0.1) * 1.02)  # a margin, so a collision at the end shows
    note = f"; constant from {shown_s - 2.0:.1f} s to the end ({end_s:.1f} s), not shown" if shown_s < end_s else ""
    axes[-1].set_xlabel("time (s)" + note)
    for ax in axes:
        ax.grid(True, alpha=0.3)
        if len(ax.get_legend_handles_labels()[1]) > 1:  # a single line is named by its y label
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9, borderaxespad=0.0)
    fit_legends(fig)
    return fig


def _gap_panel(ax, t: list, record: RunRecord) -> None:
    """The gap on a symmetric-log axis (linear within 1 m of zero), with the final gap written out."""
    gaps = [g if g < 1e9 else float("nan") for g in record.column("gap_m")]
    ax.plot(t, gaps, label="gap to the object ahead")
    ax.set_ylabel("gap (m)")
    finite = [g for g in gaps if g == g]
    if not finite:  # all NaN: nothing in the lane
        ax.text(0.5, 0.5, "no object in the lane", transform=ax.transAxes, ha="center", va="center")
        return
    ax.set_yscale("symlog", linthresh=1.0, linscale=0.6)
    ax.set_ylabel("gap (m)\n(log above 1 m)")
    top = max(finite)
    ax.set_yticks([g for g in _GAP_TICKS_M if g <= top * 1.5] + ([min(finite)] if min(finite) < 0 else []))
    ax.set_yticklabels([f"{g:g}" for g in ax.get_yticks()])
    ax.set_ylim(min(0.0, min(finite)), top * 1.5)
    final = record.metrics.final_gap_m
    if final is not None and not record.metrics.collided:
        ax.axhline(final, color="0.4", linestyle=":", linewidth=1)
        ax.text(0.99, 0.9, f"final gap {final:.2f} m", transform=ax.transAxes, ha="right", va="top", fontsize=9,
                bbox={"facecolor": "white", "edgecolor": "none", "alpha": 0.8})


def _command_panel(ax, t: list, record: RunRecord) -> None:
    """The driver's pedals as wide pale bands under the thin applied commands, so neither hides the other."""
    band = {"linewidth": 5.0, "alpha": 0.35, "solid_capstyle": "butt", "zorder": 1}
    ax.plot(t, [p / 100 for p in record.column("accel_pedal_pct")], color="C2", label="accelerator pedal", **band)
    brake_pedal = [p / 100 for p in record.column("brake_pedal_pct")]
    if any(brake_pedal):
        ax.plot(t, brake_pedal, color="C3", label="brake pedal", **band)
    ax.plot(t, record.column("throttle"), color="C0", linewidth=1.2, zorder=3, label="throttle applied")
    ax.plot(t, record.column("brake"), color="C1", linewidth=1.2, zorder=3, label="brake applied")
    ax.set_ylabel("pedal, command\n(0..1)")


def _label_startup(axes, t: list, modes: list, levels: dict[str, int]) -> None:
    """Shade and name the start-up: the ECU starts in FAULT and leaves it once every input has been valid
    for ``fault_recovery_cycles`` (:mod:`ecu.core.modes`)."""
    if not modes or modes[0] != "FAULT":
        return
    end_s = next((ti for ti, m in zip(t, modes) if m != "FAULT"), None)
    if end_s is None:
        return  # FAULT throughout: not a start-up
    for ax in axes:
        ax.axvspan(0.0, end_s, color="0.55", alpha=0.3, linewidth=0)
    axes[-1].annotate(f"start-up, 0–{end_s * 1000:.0f} ms: FAULT until the inputs are valid",
                      xy=(end_s, levels.get("FAULT", 0)), xytext=(12, -4), textcoords="offset points",
                      va="top", fontsize=8, color="0.25", arrowprops={"arrowstyle": "-", "color": "0.4"})
