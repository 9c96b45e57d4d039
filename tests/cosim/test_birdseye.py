"""The bird's-eye view of a planar run: scene.json, the pose columns, the collision, the stopping region, the plot."""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from cosim.errors import ConfigError
from cosim.results.birdseye import plot_birdseye
from cosim.results.birdseye_video import VideoOptions, _Frame, frame_indices
from cosim.results.run_view import body_box, load_run_view
from cosim.results.scene_file import Body, SceneFile, read_scene, road_to_dict, write_scene
from cosim.world.geometry import contact
from cosim.world.reference_line import Arc, Line, PlanView, Spiral
from cosim.world.road import Lane, LaneSection, LaneWidth, Road
from cosim.world.trajectory import EgoState, advance, crossing, initial_state, kinematics

EGO = Body("ego", "ego", 4.5, 1.8, 3.5)  # pose point 3.5 m behind the front (about the rear axle)
PEDESTRIAN = Body("walker", "EPTa", 0.6, 0.5, 0.3)
ROAD = Road(PlanView.chained([Line(140.0)], -60.0, 0.0, 0.0), (LaneSection.uniform(0.0, left_m=(3.5,), right_m=(3.5,)),))


def test_scene_file_round_trip(tmp_path):
    plan = PlanView.chained([Line(20.0), Spiral(15.0, 0.0, 0.04), Arc(10.0, 0.04)], 3.0, -2.0, 0.3)
    lanes = LaneSection(0.0, left=(Lane(1, (LaneWidth(0.0, 3.5), LaneWidth(10.0, 3.5, 0.05))),),
                        right=(Lane(-1, (LaneWidth(0.0, 3.25),), "shoulder"),))
    scene = SceneFile(Road(plan, (lanes,)), EGO, (PEDESTRIAN,))
    write_scene(tmp_path / "scene.json", scene)
    back = read_scene(tmp_path / "scene.json")
    assert back.ego == EGO and back.objects == (PEDESTRIAN,)
    assert road_to_dict(back.road) == road_to_dict(scene.road)
    s = np.linspace(0.0, plan.length_m, 17)
    np.testing.assert_allclose(np.array(back.road.pose(s, 1.0)), np.array(scene.road.pose(s, 1.0)), atol=1e-12)
    # lane 1 is 3.5 + 0.05 (s - 10) wide from s = 10: 4.5 m at s = 30
    assert back.road.lane_at(30.0, 4.4) == 1 and back.road.lane_at(30.0, 4.6) is None
    assert back.road.lane_at(30.0, -3.0) == -1


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(format="crd-scene/0"), "format: expected 'crd-scene/1'"),
    (lambda d: d["ego"].update(colour="red"), "ego.colour: expected one of"),
    (lambda d: d["road"]["geometry"][0].update(kind="bezier"), "road.geometry[0].kind: expected one of"),
    (lambda d: d["road"]["geometry"][0].update(length_m=-1.0), "road.geometry[0]: line: expected length_m > 0"),
    (lambda d: d["objects"][0].update(width_m="wide"), "objects[0].width_m: expected a number"),
])
def test_bad_scene_files_name_the_key_and_the_file(tmp_path, change, message):
    write_scene(tmp_path / "scene.json", SceneFile(ROAD, EGO, (PEDESTRIAN,)))
    data = json.loads((tmp_path / "scene.json").read_text())
    change(data)
    (tmp_path / "scene.json").write_text(json.dumps(data))
    with pytest.raises(ConfigError, match="scene.json: " + message.replace("[", r"\[").replace("]", r"\]")):
        read_scene(tmp_path / "scene.json")


def _planar_run(tmp_path, with_regions: bool):
    """A car at 10 m/s in the right lane and an adult crossing to meet its front at x = 40 (Euro NCAP CPNA
    synchronisation), sampled every 10 ms until the boxes first overlap, written as a planar run."""
    behaviour = crossing((40.0, -8.0), math.pi / 2, 8.0 - 1.75, 5 / 3.6, 1.0)
    state, rows, h, v = initial_state(behaviour), [], 0.01, 10.0
    for k in range(1000):
        t = k * h
        x_ego = -43.5 + v * t  # the front starts 80 m before the synchronisation point
        state = advance(behaviour, state, t, EgoState(x_ego + EGO.front_m, -1.75, 0.0, v))
        ped = kinematics(behaviour, state, t)
        rows.append((t, x_ego, -1.75, 0.0, v, "TIGHTENING", 12.0, ped.x_m, ped.y_m, ped.yaw_rad))
        if contact(body_box(EGO, x_ego, -1.75, 0.0), body_box(PEDESTRIAN, ped.x_m, ped.y_m, ped.yaw_rad)):
            break
    run = tmp_path / "run"
    (run / "tightening").mkdir(parents=True)
    write_scene(run / "scene.json", SceneFile(ROAD, EGO, (PEDESTRIAN,)))
    with open(run / "tightening" / "timeseries.csv", "w", newline="") as handle:
        out = csv.writer(handle)
        out.writerow(["time_s", "x_m", "y_m", "yaw_rad", "speed_mps", "ecu_mode", "stopping_distance_m",
                      "obj0_x_m", "obj0_y_m", "obj0_yaw_rad"])
        out.writerows(rows)
    (run / "tightening" / "events.json").write_text(json.dumps(
        {"events": [{"t_s": rows[-1][0], "kind": "collision", "detail": "x"}], "error": None}))
    (run / "metrics.json").write_text(json.dumps({"runs": [{"strategy": "tightening", "impact_speed_mps": 10.0}]}))
    if with_regions:
        regions = {"t_s": [0.0, 1.0], "polygons": [[], [[x, y] for x, y in ((0, 0), (5, 0), (5, 2), (0, 2))]]}
        (run / "tightening" / "stopping_region.json").write_text(json.dumps(regions))
    return run, rows


def test_a_planar_run_is_read_with_its_collision(tmp_path):
    run, rows = _planar_run(tmp_path, with_regions=False)
    track = load_run_view(run).tracks["tightening"]
    assert track.ego[-1] == pytest.approx(rows[-1][1:4])
    assert track.objects[0, -1] == pytest.approx(rows[-1][7:10])
    # the walker meets the front of the car (x = front) within what one 10 ms sample allows
    hit = track.collision
    front = rows[-1][1] + EGO.front_m
    assert hit.x_m == pytest.approx(front - 0.5 * 0.1, abs=0.06) and hit.object_index == 0
    assert -1.75 - 0.9 <= hit.y_m <= -1.75 + 0.9  # on the car's front, within its width
    expected = contact(body_box(EGO, *rows[-1][1:4]), body_box(PEDESTRIAN, *rows[-1][7:10]))
    assert (hit.x_m, hit.y_m) == pytest.approx((expected.x_m, expected.y_m))
    assert hit.impact_speed_mps == 10.0


def test_the_birdseye_plot_is_written(tmp_path):
    run, _ = _planar_run(tmp_path, with_regions=False)
    png = plot_birdseye(load_run_view(run), "tightening", tmp_path / "b.png")
    from PIL import Image

    with Image.open(png) as image:
        assert image.size == (1200, 750)
        pixels = np.asarray(image.convert("RGB")).reshape(-1, 3)
    crimson = (pixels == (220, 20, 60)).all(axis=1).sum()  # the collision marks
    assert crimson > 50


def test_the_video_frame_draws_the_stopping_region_or_the_1d_stopping_path(tmp_path):
    run, rows = _planar_run(tmp_path, with_regions=True)
    view = load_run_view(run)
    frame = _Frame(view, view.tracks["tightening"], VideoOptions(width_px=640))
    frame.draw(10)  # t = 0.1 s: the empty polygon
    assert not frame.stopping.get_visible()
    frame.draw(150)  # t = 1.5 s: the square
    assert frame.stopping.get_visible()
    assert frame.stopping.get_xy()[:4] == pytest.approx(np.array([(0, 0), (5, 0), (5, 2), (0, 2)]))
    (run / "tightening" / "stopping_region.json").unlink()
    view = load_run_view(run)
    frame = _Frame(view, view.tracks["tightening"], VideoOptions(width_px=640))
    frame.draw(150)  # 12 m ahead of the front, the car's width
    front = rows[150][1] + EGO.front_m
    xy = frame.stopping.get_xy()[:4]
    assert sorted(xy[:, 0]) == pytest.approx([front, front, front + 12.0, front + 12.0])
    assert sorted(xy[:, 1]) == pytest.approx([-2.65, -2.65, -0.85, -0.85])


def test_frames_are_taken_at_the_video_rate():
    t = np.round(np.arange(0, 201) * 0.01, 10)  # 0 .. 2.00 s every 10 ms
    idx = frame_indices(t, 25.0)
    assert len(idx) == 51 and idx[:3].tolist() == [0, 4, 8] and idx[-1] == 200
    assert len(frame_indices(t, 12.5, playback=2.0)) == 13  # 0.16 s of simulation per frame
