"""``crd animate`` end to end on a short run of today's 1-D world: an MP4 and a GIF, their frames and sizes."""

from __future__ import annotations

import csv

import imageio_ffmpeg
import numpy as np
import pytest
from PIL import Image

from cosim.cli.main import main as crd
from cosim.results.run_view import load_run_view

SHORT = """
[scenario]
name = "animate_short"
duration_s = 2.0

[plant]
fmu = "builtin"
initial_speed_mps = 10.0

[driver]
model = "full_throttle"

[object]
position_m = 30.0
speed_mps = 5.0
brake_decel_mps2 = 4.0
brake_at_gap_m = 20.0

[ecu]
strategy = "tightening"
"""


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    """A 2 s run: the ego from 10 m/s behind a car at 5 m/s that brakes when the gap falls to 20 m."""
    root = tmp_path_factory.mktemp("animate")
    (root / "s.toml").write_text(SHORT)
    assert crd(["run", str(root / "s.toml"), "--out", str(root / "run")]) == 0
    return root / "run"


def _column(run, name):
    with open(run / "tightening" / "timeseries.csv", newline="") as handle:
        return np.array([float(r[name]) for r in csv.DictReader(handle)])


def test_a_1d_run_is_replayed_with_its_triggers_and_stopping_distances(short_run):
    track = load_run_view(short_run).tracks["tightening"]
    bumper = _column(short_run, "position_m")  # the builtin plant's front bumper offset is 0
    rear = track.objects[0, :, 0] - 1.8 / 2  # the object's default length
    gap = _column(short_run, "gap_m")
    assert np.abs(rear - bumper - gap).max() < 1e-3  # the replayed object is where the run saw it
    speed = np.diff(track.objects[0, :, 0]) / np.diff(track.t_s)
    assert speed[0] == pytest.approx(5.0) and speed[-1] < 4.0  # its gap trigger fired: it brakes
    # EcuStatus every 100 ms from t = 0: the stopping distance is held between reports and changes only at them
    assert np.isfinite(track.stopping_m).all() and (track.stopping_m > 1.0).all()
    changes = track.t_s[1:][np.diff(track.stopping_m) != 0]
    assert len(changes) > 5 and np.allclose(np.round(changes * 10), changes * 10)


def test_crd_animate_writes_an_mp4_and_a_gif(short_run, capsys):
    last_t = _column(short_run, "time_s")[-1]
    assert crd(["animate", str(short_run), "--hold-s", "0.4"]) == 0
    mp4 = short_run / "tightening" / "birdseye.mp4"
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(mp4))
    assert frames == int(np.floor(last_t * 25 + 1e-9)) + 1 + 10
    reader = imageio_ffmpeg.read_frames(str(mp4))
    meta = next(reader)
    assert tuple(meta["size"]) == (1280, 720) and meta["fps"] == 25.0
    reader.close()
    with Image.open(short_run / "tightening" / "birdseye.png") as png:
        assert png.size == (1200, 750)
    out = capsys.readouterr().out
    assert "birdseye.mp4" in out and "birdseye.png" in out

    gif = short_run / "clip.gif"
    assert crd(["animate", str(short_run), "--out", str(gif), "--no-png", "--hold-s", "0"]) == 0
    with Image.open(gif) as image:
        assert image.size == (640, 360)
        assert image.n_frames == int(np.floor(last_t * 12.5 + 1e-9)) + 1
        assert image.info["duration"] == 80  # 12.5 frames per second


def test_animate_errors_are_one_line(short_run, tmp_path, capsys):
    assert crd(["animate", str(tmp_path)]) == 1
    assert capsys.readouterr().err.startswith(f"error: {tmp_path}: not a crd run directory")
    assert crd(["animate", str(short_run), "--out", str(tmp_path / "x.avi")]) == 1
    assert "expected a video suffix in ['.gif', '.mp4']" in capsys.readouterr().err
    assert crd(["animate", str(short_run), "--strategy", "none"]) == 1
    assert "no time series for strategy 'none'" in capsys.readouterr().err
    assert crd(["animate", str(short_run), "--width", "1000"]) == 1
    assert "steps of 32" in capsys.readouterr().err


def test_crd_run_video_writes_the_mp4_and_the_plot_of_a_1d_run(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(SHORT)
    assert crd(["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "plain")]) == 0
    assert not (tmp_path / "plain" / "tightening" / "birdseye.png").exists()  # a 1-D run draws none by itself
    assert crd(["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "run"), "--video"]) == 0
    last_t = _column(tmp_path / "run", "time_s")[-1]
    frames, _ = imageio_ffmpeg.count_frames_and_secs(str(tmp_path / "run" / "tightening" / "birdseye.mp4"))
    assert frames == int(np.floor(last_t * 25 + 1e-9)) + 1 + 25  # crd animate's defaults: 25 fps, 1 s hold
    with Image.open(tmp_path / "run" / "tightening" / "birdseye.png") as png:
        assert png.size == (1200, 750)
    assert "birdseye.mp4" in capsys.readouterr().out
