"""The four bundled planar scenarios, run by ``crd run`` with today's longitudinal ECU: what physically happens.

Each run is read back from its files (the bird's-eye view's :func:`~cosim.results.run_view.load_run_view`);
the distances between the ego's box and the objects' boxes are measured with shapely, the geometry
tests' independent oracle. ``crd run --video`` is tested on the crossing run.
"""

from __future__ import annotations

import csv
import json

import imageio_ffmpeg
import numpy as np
import pytest
from shapely.geometry import Polygon

from cosim.cli.main import main as crd
from cosim.results.run_view import RunView, body_box, load_run_view


def run(tmp_path, name: str, *extra: str) -> tuple[RunView, dict, str]:
    """``crd run NAME`` into ``tmp_path/NAME``: the run's view, its metrics and its strategy."""
    out = tmp_path / name
    assert crd(["run", name, "--out", str(out), *extra]) == 0
    metrics = json.loads((out / "metrics.json").read_text())["runs"][0]
    return load_run_view(out), metrics, metrics["strategy"]


def column(view: RunView, strategy: str, name: str) -> list[str]:
    with open(view.path / strategy / "timeseries.csv", newline="") as handle:
        return [row[name] for row in csv.DictReader(handle)]


def clearances_m(view: RunView, strategy: str, i: int) -> np.ndarray:
    """Per sample, the distance (m) between the ego's box and object ``i``'s box (0: touching)."""
    track = view.tracks[strategy]

    def polygon(body, pose):
        return Polygon(body_box(body, *(float(v) for v in pose)).corners())

    return np.array([polygon(view.ego, e).distance(polygon(view.objects[i], o))
                     for e, o in zip(track.ego, track.objects[i])])


def test_lane_change_passes_the_parked_car_without_braking(tmp_path):
    view, metrics, strategy = run(tmp_path, "lane_change_parked_car")
    track = view.tracks[strategy]
    assert not metrics["collided"] and (view.path / strategy / "birdseye.png").is_file()
    gaps = clearances_m(view, strategy, 0)
    alongside = np.abs(track.ego[:, 0] - track.objects[0, :, 0]) < 3.0  # the car's centre beside the ego's
    assert alongside.any() and gaps[alongside].min() > 1.0  # a lane's width beside it, not a graze
    assert track.ego[alongside, 1].min() > 2.5  # in the left lane (centre y = 3.5 m) while passing
    assert abs(track.ego[-1, 1]) < 0.3 and track.ego[-1, 0] > track.objects[0, -1, 0] + 50.0  # back in its lane
    # today's ECU watches the path ahead along the heading: the parked car is beside it by the time it
    # would matter, so it never brakes, and the driver's 50 km/h holds throughout
    assert set(column(view, strategy, "ecu_mode")[10:]) == {"STANDBY"}
    assert track.speed_mps.min() > 13.5


def test_curve_keeps_its_lane_past_the_parked_car_and_the_ecu_lets_it_pass_at_speed(tmp_path):
    view, metrics, strategy = run(tmp_path, "curve_parked_car")
    track = view.tracks[strategy]
    assert not metrics["collided"]
    offsets = np.array([view.road.to_st(x, y)[1] for x, y, _ in track.ego]) + 1.75  # from lane -1's centre
    assert np.abs(offsets).max() < 0.5  # the path-following driver holds the lane through the 100 m arc
    assert track.ego[:, 2].max() > 1.5  # and it did turn through the arc (pi / 2)
    # the parked car on the outside is passed with room: 1.24 m between the boxes with the ego on its lane's centre
    assert clearances_m(view, strategy, 0).min() > 1.0
    # no false positive since issue 22's false-positive round: the parked car's box stands along the road (it was
    # placed on the ego's axes and widened across our lane at its corner near the bore sight), so the region
    # invokes nothing and the 50 km/h holds (the driver's speed control dips 0.15 m/s in the arc)
    modes = column(view, strategy, "ecu_mode")
    assert set(modes) <= {"FAULT", "STANDBY"} and "STANDBY" in modes  # FAULT: the first cycles, before the frames
    assert track.speed_mps.min() > 13.5


def test_crossing_pedestrian_is_stopped_for(tmp_path):
    view, metrics, strategy = run(tmp_path, "crossing_pedestrian", "--video")
    track = view.tracks[strategy]
    assert not metrics["collided"] and metrics["end_reason"] == "standstill" and track.speed_mps[-1] < 0.01
    gaps = clearances_m(view, strategy, 0)
    assert 2.0 < gaps.min() < 10.0  # stopped a few metres short
    # ... of a pedestrian who really walked across its path: the centre crossing the ego's width just ahead
    ahead = track.objects[0, :, 0] - (track.ego[:, 0] + view.ego.front_m)
    assert ((np.abs(track.objects[0, :, 1]) < view.ego.width_m / 2) & (ahead > 0.0) & (ahead < 10.0)).any()
    # crd run --video: crd animate's MP4 (25 fps, 1280 x 720, the last frame held 1 s) and the plot
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(view.path / strategy / "birdseye.mp4"))
    assert frames == int(np.floor(track.t_s[-1] * 25 + 1e-9)) + 1 + 25
    assert "birdseye.png" in (view.path / "report.md").read_text()
    # the contingency alone (strategy none: no stopping path is tightened) stops it too, but later and nearer
    view, metrics, strategy = run(tmp_path / "none", "crossing_pedestrian", "--strategy", "none")
    assert not metrics["collided"] and metrics["contingency_invocations"] >= 1
    assert 0.0 < clearances_m(view, strategy, 0).min() < gaps.min() - 2.0


def test_the_paper_scene_with_the_wheel_free_is_the_1d_run_bit_for_bit(tmp_path):
    view, metrics, strategy = run(tmp_path, "paper_cyclist_road")
    line, line_metrics, _ = run(tmp_path, "paper_cyclist", "--strategy", strategy)
    # nothing pushes a symmetric car on a flat road sideways: it never leaves y = 0, heading 0 ...
    assert set(column(view, strategy, "y_m")) == {"0"} and set(column(view, strategy, "yaw_rad")) == {"0"}
    # ... so every longitudinal column is today's 1-D run's, to the last digit, and the ECU stops it short
    for name in ("time_s", "position_m", "speed_mps", "accel_mps2", "throttle", "brake", "ecu_mode", "gap_m"):
        assert column(view, strategy, name) == column(line, strategy, name), name
    assert not metrics["collided"] and metrics["final_gap_m"] == line_metrics["final_gap_m"]
    # the boxes from the time series' poses (written to 6 significant digits) leave the same gap
    assert 2.0 < metrics["final_gap_m"] < 5.0
    assert clearances_m(view, strategy, 0)[-1] == pytest.approx(metrics["final_gap_m"], abs=1e-3)
