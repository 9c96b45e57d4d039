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
