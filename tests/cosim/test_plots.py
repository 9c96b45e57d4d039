"""Plots a person would rather look at (issue 13, finding 7): timelines trimmed to the active part,
the collision marked, legends outside every axes, and a zoomed panel before the object."""

import pytest

from cosim.loop.master import run_scenario
from cosim.results.plots import Profile, active_end_s, collision_point, profile_figure, timeline_figure
from cosim.scenarios.loader import scenario_from_dict

OBJECT_M = 100.0


@pytest.fixture(scope="module")
def records(plant_fmu3):
    sc = scenario_from_dict({"scenario": {"duration_s": 20.0}, "object": {"position_m": OBJECT_M},
                             "radar": {"latency_s": 0.1}})
    return {s: run_scenario(sc, plant_fmu3, s) for s in ("none", "conservative")}


def _legends_cover_nothing(fig) -> None:
    fig.canvas.draw()
    legends = list(fig.legends) + [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert legends
    for legend in legends:
        box = legend.get_window_extent()
        for ax in fig.axes:
            assert not box.overlaps(ax.get_window_extent()), f"legend over the axes {ax.get_title()!r}"


def test_timeline_is_trimmed_to_the_active_part(records):
    rec = records["conservative"]
    assert not rec.metrics.collided and rec.metrics.sim_time_s == pytest.approx(20.0)
    active = active_end_s(rec)
    assert 5.0 < active < 12.0  # stopped; nothing changes after that
    fig = timeline_figure(rec)
    right = fig.axes[-1].get_xlim()[1]
    assert active < right < active + 3.0
    assert f"constant from {active:.1f} s to the end (20.0 s), not shown" in fig.axes[-1].get_xlabel()
    _legends_cover_nothing(fig)


def test_collision_is_marked(records):
    rec = records["none"]
    assert rec.metrics.collided
    hit = collision_point(rec)
    assert hit.speed_mps == pytest.approx(rec.metrics.impact_speed_mps, abs=0.05)
    assert hit.position_m == pytest.approx(OBJECT_M, abs=0.05)
    fig = timeline_figure(rec)
    marks = [line for ax in fig.axes for line in ax.get_lines() if list(line.get_xdata()) == [hit.t_s] * 2]
    assert len(marks) == len(fig.axes) == 5  # a vertical line through every panel
    assert fig.axes[-1].get_xlim()[1] > hit.t_s  # and not on the frame
    profiles = profile_figure([Profile(s, r) for s, r in records.items()], OBJECT_M, "t")
    labels = [line.get_label() for line in profiles.axes[0].get_lines()]
    assert f"none: collision at {hit.speed_mps:.2f} m/s" in labels


def test_speed_profiles_zoom_before_the_object(records):
    fig = profile_figure([Profile(s, r) for s, r in records.items()], OBJECT_M, "t", split_m=80.0)
    full, zoom = fig.axes
    assert zoom.get_xlim() == pytest.approx((OBJECT_M - 75.0, OBJECT_M + 2.0))
    assert full.get_xlim()[0] < 0.0 < OBJECT_M < full.get_xlim()[1]
    assert any(line.get_label() == "claim 4 split (80 m)" for line in zoom.get_lines())
    _legends_cover_nothing(fig)


# -- plots that explain themselves (issue 24, item 6) ---------------------------------------------


def test_contingency_invocations_are_marked_where_they_happened(records):
    """Each marker sits on its run's line where the mode entered CONTINGENCY; their number is the
    run's own count (the gateway's), worked out here a second way."""
    fig = profile_figure([Profile(s, r) for s, r in records.items()], OBJECT_M, "t", object_name="cyclist")
    full = fig.axes[0]
    for strategy, rec in records.items():
        n = rec.metrics.contingency_invocations
        assert n >= 1
        marks = [line for line in full.get_lines()
                 if line.get_label() == f"{strategy}: ECU intervened (contingency) ×{n}"]
        assert len(marks) == 1, [line.get_label() for line in full.get_lines()]
        rows = rec.rows
        onsets = [(rows[i][1], rows[i][2]) for i in range(1, len(rows))
                  if rows[i][6] == "CONTINGENCY" != rows[i - 1][6]]
        assert list(zip(marks[0].get_xdata(), marks[0].get_ydata())) == onsets


def test_the_object_is_named_and_both_panels_label_their_axes(records):
    fig = profile_figure([Profile(s, r) for s, r in records.items()], OBJECT_M, "t", object_name="cyclist")
    labels = {line.get_label() for ax in fig.axes for line in ax.get_lines()}
    assert "cyclist at 100 m" in labels and not any(lab.startswith("object") for lab in labels)
    assert [ax.get_xlabel() for ax in fig.axes] == ["position (m)"] * 2  # the top panel too


def test_legends_stay_on_the_figure(records):
    """A long legend entry widens the figure instead of running off its right edge (crd compare's
    legend was clipped)."""
    long = "A: " + "a-long-run-directory-name/" * 3 + "none"
    fig = profile_figure([Profile(long, records["none"], "--")], OBJECT_M, "t")
    fig.canvas.draw()
    assert fig.get_figwidth() > 10.5  # widened
    assert fig.legends[0].get_window_extent().x1 <= fig.bbox.x1
    _legends_cover_nothing(fig)


def test_timeline_has_deceleration_and_a_gap_axis_that_shows_the_last_metres(records):
    rec = records["conservative"]
    fig = timeline_figure(rec)
    speed, gap, decel, commands, mode = fig.axes
    assert list(decel.get_lines()[0].get_ydata()) == [-a for a in rec.column("accel_mps2")]
    assert "deceleration" in decel.get_ylabel()
    assert gap.get_yscale() == "symlog"
    final = rec.metrics.final_gap_m
    assert 0.5 < final < 5.0
    lo, hi = gap.get_ylim()
    # a final gap of a few metres takes a visible share of the panel's height (on a linear
    # 0..150 m axis it would be under 3 %)
    share = (gap.transData.transform((0, final))[1] - gap.transData.transform((0, lo))[1]) / gap.bbox.height
    assert share > 0.2 and hi > max(g for g in rec.column("gap_m") if g < 1e9)
    assert f"final gap {final:.2f} m" in [t.get_text() for t in gap.texts]


def test_pedals_lie_under_the_applied_commands(records):
    fig = timeline_figure(records["none"])
    lines = {line.get_label(): line for line in fig.axes[3].get_lines()}
    pedal, throttle = lines["accelerator pedal"], lines["throttle applied"]
    assert pedal.get_zorder() < throttle.get_zorder() and pedal.get_linewidth() > 2 * throttle.get_linewidth()
    assert list(pedal.get_ydata()) == [p / 100 for p in records["none"].column("accel_pedal_pct")]


def test_the_start_up_is_labelled(records):
    rec = records["none"]
    modes = rec.column("ecu_mode")
    assert modes[0] == "FAULT"
    end_s = next(t for t, m in zip(rec.column("time_s"), modes) if m != "FAULT")
    assert 0.0 < end_s < 0.5
    fig = timeline_figure(rec)
    notes = [t.get_text() for t in fig.axes[-1].texts]
    assert notes == [f"start-up, 0–{end_s * 1000:.0f} ms: FAULT until the inputs are valid"]
    for ax in fig.axes:  # shaded in every panel, exactly to the end of the start-up
        spans = [p for p in ax.patches if p.get_x() == 0.0 and p.get_width() == pytest.approx(end_s)]
        assert len(spans) == 1
