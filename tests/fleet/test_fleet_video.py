"""The fleet run directory describes itself (``fleet.json``) and ``crd animate`` draws every car of it: the MP4,
the GIF and the still, the stopping paths in the world, the outlines in the modes' colours, one-line errors."""

from __future__ import annotations

import json

import imageio_ffmpeg
import numpy as np
import pytest
from matplotlib.colors import to_rgba
from PIL import Image

from cosim.cli.fleet import find_scene
from cosim.cli.main import main as crd
from cosim.errors import ConfigError
from cosim.fleet.config import load_fleet
from cosim.fleet.run_view import load_fleet_view
from cosim.fleet.scene_file import (
    FLEET_SCENE_FILE, fleet_scene_of, read_fleet_scene, scene_to_dict, write_fleet_scene,
)
from cosim.fleet.video import FleetFrame
from cosim.results.birdseye_video import MODE_COLORS, VideoOptions


@pytest.fixture(scope="module")
def fleet_run(tmp_path_factory):
    """The crossing with human drivers under the plain method: both cars brake too late and touch at 3.77 s."""
    out = tmp_path_factory.mktemp("fleet_video") / "crossing_reacting"
    assert crd(["fleet", "crossing_reacting", "--strategy", "none", "--out", str(out)]) == 3
    return out


def test_the_scene_file_is_written_and_reads_back_in_world_coordinates(fleet_run):
    scene = read_fleet_scene(fleet_run / FLEET_SCENE_FILE)
    assert [c.name for c in scene.cars] == ["west", "south"]
    assert scene.conflict == (0.0, 0.0, 6.0) and scene.name == "crossing_reacting"
    west, south = scene.cars
    assert (south.frame.x_m, south.frame.y_m, south.frame.heading_rad) == (0.0, -40.0, pytest.approx(np.pi / 2))
    assert west.body.length_m > 4.0 and west.body.width_m > 1.5
    # each road: 120 m along its car's x axis from its frame's origin, its left edge 5.25 m to the car's left
    assert west.road.left[0] == pytest.approx([-40.0, 5.25]) and west.road.left[-1] == pytest.approx([80.0, 5.25])
    assert south.road.left[0] == pytest.approx([-5.25, -40.0]) and south.road.right[-1] == pytest.approx([1.75, 80.0])
    assert len(west.road.markings) == 1  # the centre line between the two directions


def test_the_world_objects_read_back(tmp_path):
    fleet = load_fleet(find_scene("narrow_passage"))
    write_fleet_scene(tmp_path / FLEET_SCENE_FILE, fleet_scene_of(fleet))
    back = read_fleet_scene(tmp_path / FLEET_SCENE_FILE)
    assert [(o.body.name, o.x_m, o.y_m, o.body.length_m) for o in back.objects] == \
        [(o.name, o.pose.x_m, o.pose.y_m, o.length_m) for o in fleet.objects]
    assert len(back.objects) >= 2
    data = scene_to_dict(back)
    data["vehicles"][1]["colour"] = "red"
    (tmp_path / FLEET_SCENE_FILE).write_text(json.dumps(data))
    with pytest.raises(ConfigError, match=r"fleet.json: vehicles\[1\].colour: expected one of"):
        read_fleet_scene(tmp_path / FLEET_SCENE_FILE)


def _index(view, t_s):
    return int(np.searchsorted(view.t_s, t_s - 1e-9))


def test_every_car_s_stopping_path_is_drawn_ahead_of_it_in_the_world(fleet_run):
    view = load_fleet_view(fleet_run)
    frame = FleetFrame(view, VideoOptions(width_px=640))
    j = _index(view, 1.0)  # both cars at 30 km/h: the ECUs report the driver's path, 5 m or so
    frame.draw(j)
    west, south = (car.region for car in frame.cars)
    assert west.get_visible() and south.get_visible()
    (wx, wy, _), (sx, sy, _) = view.tracks[0].box[j], view.tracks[1].box[j]
    half = view.scene.cars[0].body.length_m / 2
    band = west.get_xy()
    assert band[:, 0].min() == pytest.approx(wx + half) and band[:, 0].max() > wx + half + 3.0
    assert np.abs(band[:, 1] - wy).max() == pytest.approx(view.scene.cars[0].body.width_m / 2)
    band = south.get_xy()  # the south car heads +y: its path is moved by its frame
    assert band[:, 1].min() == pytest.approx(sy + half) and band[:, 1].max() > sy + half + 3.0
    assert np.abs(band[:, 0] - sx).max() == pytest.approx(view.scene.cars[1].body.width_m / 2)
    for car, track in zip(frame.cars, view.tracks):
        assert car.box.get_edgecolor() == to_rgba(MODE_COLORS[track.mode[j]])
    assert not frame.hits.get_visible()
    frame.draw(len(view.t_s) - 1)
    assert frame.hits.get_visible() and len(frame.hits.get_xdata()) == 2  # each car's contact point
    assert np.hypot(frame.hits.get_xdata(), frame.hits.get_ydata()).max() < 3.0  # at the crossing


def test_crd_animate_writes_the_fleet_mp4_gif_and_still(fleet_run, capsys):
    last_t = load_fleet_view(fleet_run).t_s[-1]
    assert last_t == pytest.approx(3.77)
    assert crd(["animate", str(fleet_run), "--hold-s", "0.4", "--at-s", "3.0"]) == 0
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(fleet_run / "fleet.mp4"))
    assert frames == int(np.floor(last_t * 25 + 1e-9)) + 1 + 10
    with Image.open(fleet_run / "fleet.png") as png:
        assert png.size == (1280, 720)
    out = capsys.readouterr().out
    assert f"fleet.mp4 ({frames} frames, 1280x720, 25 fps)" in out and "fleet.png (t = 3.00 s)" in out

    assert crd(["animate", str(fleet_run), "--gif", "--no-png", "--hold-s", "0"]) == 0
    with Image.open(fleet_run / "fleet.gif") as gif:
        assert gif.size == (640, 360)
        assert gif.n_frames == int(np.floor(last_t * 12.5 + 1e-9)) + 1


def test_animate_errors_are_one_line(fleet_run, tmp_path, capsys):
    assert crd(["animate", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"error: {tmp_path}: not a crd run directory") and "fleet.json" in err
    assert err.count("\n") == 1
    assert crd(["animate", str(fleet_run), "--strategy", "none"]) == 1
    assert capsys.readouterr().err.count("\n") == 1
    (tmp_path / "metrics.json").write_text(json.dumps({"fleet": "old", "vehicles": {}}))  # a fleet run before fleet.json
    assert crd(["animate", str(tmp_path)]) == 1
    assert "has no runs" in capsys.readouterr().err
