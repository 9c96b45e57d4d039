"""Runs as ROS 2 / MCAP (issue 24, item 4): ``crd run --record`` and ``crd export --format mcap``.

The file is read back with the ``mcap`` reader and mcap-ros2-support's CDR decoder (not the
rosbags serializer that wrote it), and again with rosbags from the schemas in the file alone;
every topic's count and first message are checked against the run's own files, read here
independently: ``timeseries.csv`` with :mod:`csv`, ``can.blf`` with python-can, the signals
with crd's receiver (not cantools), ``events.json`` with :mod:`json`.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import can
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory

from can_dbc import LAYOUTS_BY_ID, Receiver, write_key_file
from cosim.cli.main import main as crd
from cosim.results.mcap_schemas import field_name

START_NS = 1_577_836_800 * 10**9  # [scenario] start_time's default, 2020-01-01T00:00:00Z
SCENARIO = """
[scenario]
duration_s = 6.0

[[objects]]
name = "cyclist"
position_m = 40.0
length_m = 1.8

[[objects]]
name = "passing bike"
position_m = 10.0
lateral_m = 3.5
speed_mps = 2.0
length_m = 1.7
width_m = 0.6

[ecu]
strategy = "none"

[end]
standstill = true
"""
PLANT_LENGTH_M, PLANT_WIDTH_M = 4.358, 1.815  # [plant] defaults


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A run with two objects (one standing in the lane, one moving beside it), recorded as it ran."""
    root = tmp_path_factory.mktemp("mcap")
    (root / "two.toml").write_text(SCENARIO)
    write_key_file(root / "secoc.key", bytes(range(16)))  # a fixed key: the same MACs in each run
    assert crd(["run", str(root / "two.toml"), "--out", str(root / "run"), "--record", str(root / "run.mcap"),
                "--key-file", str(root / "secoc.key")]) == 0
    return root


def _read(path: Path) -> dict[str, list]:
    """topic -> [(log time, decoded message)], by the mcap reader and mcap-ros2-support's decoder."""
    topics: dict[str, list] = {}
    with open(path, "rb") as handle:
        reader = make_reader(handle, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        for schema, channel, message, decoded in reader.iter_decoded_messages():
            assert (schema.encoding, channel.message_encoding) == ("ros2msg", "cdr")
            topics.setdefault(channel.topic, []).append((message.log_time, decoded))
    return topics


def _rows(run: Path) -> list[dict[str, str]]:
    with open(run / "none" / "timeseries.csv", newline="") as handle:
        return list(csv.DictReader(handle))


def _ns(t_s: str | float) -> int:
    return START_NS + round(float(t_s) * 1e6) * 1000


@pytest.fixture(scope="module")
def contents(recorded):
    with can.BLFReader(str(recorded / "run" / "none" / "can.blf")) as reader:
        frames = list(reader)
    events = json.loads((recorded / "run" / "none" / "events.json").read_text())["events"]
    return _read(recorded / "run.mcap"), _rows(recorded / "run"), frames, events


def test_every_topic_is_there_and_no_other(contents):
    topics, _, frames, _ = contents
    decoded = {f"/can/decoded/{LAYOUTS_BY_ID[f.arbitration_id].name}" for f in frames
               if f.arbitration_id in LAYOUTS_BY_ID}
    # the five of the 1-D contract: a 1-D scene equips the ECU with no planar sensor nor steering (ecu.equipment)
    assert decoded == {f"/can/decoded/{name}" for name in
                       ("DriverInput", "WheelSpeeds", "ObjectTrack", "SafetyOverride", "EcuStatus")}
    assert set(topics) == {"/can/frames", "/run/sample", "/ego/odometry", "/tf", "/scene/markers",
                           "/run/events"} | decoded


def test_can_frames_and_their_signals(contents):
    topics, _, frames, _ = contents
    assert len(topics["/can/frames"]) == len(frames) > 1000
    t, first = topics["/can/frames"][0]
    assert t == _ns(frames[0].timestamp - START_NS / 1e9)
    assert (first.id, first.dlc, bytes(first.data), first.is_extended) == \
        (frames[0].arbitration_id, frames[0].dlc, bytes(frames[0].data), False)
    assert [m.id for _, m in topics["/can/frames"]] == [f.arbitration_id for f in frames]  # every frame, in order
    receiver = Receiver()
    for frame_id, layout in LAYOUTS_BY_ID.items():
        mine = [f for f in frames if f.arbitration_id == frame_id]
        if not mine:
            continue
        messages = topics[f"/can/decoded/{layout.name}"]
        assert len(messages) == len(mine)
        checked = receiver.check(mine[0])  # crd's own decoder: DBC units
        t, first = messages[0]
        assert t == _ns(mine[0].timestamp - START_NS / 1e9) and first.counter == checked.counter
        for name, value in checked.signals.items():
            assert getattr(first, field_name(layout.name, name)) == pytest.approx(value, abs=1e-9), name


def test_samples_odometry_and_transforms_follow_the_time_series(contents):
    topics, rows, _, _ = contents
    for topic in ("/run/sample", "/ego/odometry", "/tf"):
        assert len(topics[topic]) == len(rows) > 500, topic
    t, sample = topics["/run/sample"][0]
    assert t == _ns(rows[0]["time_s"]) == START_NS
    for column, text in rows[0].items():
        assert getattr(sample, column) == (text if column == "ecu_mode" else float(text)), column
    for row, (t, odom), (_, tf) in zip(rows, topics["/ego/odometry"], topics["/tf"]):
        assert t == _ns(row["time_s"])
        assert odom.pose.pose.position.x == float(row["position_m"]) and odom.pose.pose.position.y == 0.0
        assert odom.twist.twist.linear.x == float(row["speed_mps"])
        assert (odom.header.frame_id, odom.child_frame_id) == ("map", "base_link")
        ego, cyclist, bike = tf.transforms
        assert (ego.child_frame_id, ego.transform.translation.x) == ("base_link", float(row["position_m"]))
        # the objects replayed: the cyclist stands, the bike rides at 2 m/s from 10 m, 3.5 m to the left
        assert (cyclist.child_frame_id, cyclist.transform.translation.x) == ("object_0", 40.0 + 0.9)
        expected_x = 10.0 + 2.0 * float(row["time_s"]) + 0.85
        assert bike.child_frame_id == "object_1" and bike.transform.translation.y == 3.5
        assert bike.transform.translation.x == pytest.approx(expected_x, abs=1e-9)


def _stopping_distances(frames) -> list[tuple[int, float]]:
    receiver = Receiver()
    status = [f for f in frames if LAYOUTS_BY_ID.get(f.arbitration_id) and
              LAYOUTS_BY_ID[f.arbitration_id].name == "EcuStatus"]
    return [(_ns(f.timestamp - START_NS / 1e9), receiver.check(f).signals["StoppingDistance"]) for f in status]


def test_the_scene_is_written_when_it_changes(contents):
    topics, rows, frames, _ = contents
    status, k, last, changes = _stopping_distances(frames), 0, None, []
    for row in rows:  # the last stopping distance at or before each row, and the rows where the scene changes
        while k < len(status) and status[k][0] <= _ns(row["time_s"]):
            last, k = status[k][1], k + 1
        if not changes or (row["ecu_mode"], last) != changes[-1][1:]:
            changes.append((_ns(row["time_s"]), row["ecu_mode"], last))
    scenes = topics["/scene/markers"]
    assert [t for t, _ in scenes] == [t for t, _, _ in changes] and len(scenes) > 10
    t, mode, distance = next(c for c in changes if c[2] is not None and c[2] > 1.0)
    markers = {(m.ns, m.id): m for m in dict(scenes)[t].markers}
    assert set(markers) == {("ego", 0), ("objects", 0), ("objects", 1), ("object_names", 0), ("object_names", 1),
                            ("stopping_path", 0)}
    ego, path = markers["ego", 0], markers["stopping_path", 0]
    assert (ego.scale.x, ego.scale.y) == (PLANT_LENGTH_M, PLANT_WIDTH_M) and ego.header.frame_id == "base_link"
    assert ego.pose.position.x == pytest.approx(-PLANT_LENGTH_M / 2)  # behind the front bumper
    assert [p.x for p in path.points] == pytest.approx([0.0, distance]) and path.frame_locked
    assert markers["object_names", 1].text == "passing bike" and markers["objects", 1].header.frame_id == "object_1"
    assert (markers["objects", 0].scale.x, markers["objects", 0].scale.y) == (1.8, 0.6)


def test_events_are_log_lines(contents):
    topics, _, _, events = contents
    assert len(topics["/run/events"]) == len(events) == 1
    t, line = topics["/run/events"][0]
    assert t == _ns(events[0]["t_s"]) and line.msg == f"{events[0]['kind']}: {events[0]['detail']}"
    assert line.level == 20 and line.name == "crd"  # INFO


def test_rosbags_reads_it_from_its_own_schemas(recorded, contents):
    """rosbags, given no types of its own, deserializes every message from the schemas in the file."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    topics = contents[0]
    counts: dict[str, int] = {}
    with AnyReader([recorded / "run.mcap"], default_typestore=get_typestore(Stores.EMPTY)) as reader:
        for connection, _, raw in reader.messages():
            reader.deserialize(raw, connection.msgtype)
            counts[connection.topic] = counts.get(connection.topic, 0) + 1
        types = {c.topic: c.msgtype for c in reader.connections}
    assert counts == {topic: len(messages) for topic, messages in topics.items()}
    assert types["/can/frames"] == "can_msgs/msg/Frame" and types["/scene/markers"] == \
        "visualization_msgs/msg/MarkerArray" and types["/can/decoded/SafetyOverride"] == \
        "crd_can_msgs/msg/SafetyOverride"


def test_record_equals_export_and_is_deterministic(recorded, capsys):
    """``--record`` writes what ``crd export`` writes, byte for byte, and a second run of the same
    scenario gives the same file again: every time is the start time plus simulated time."""
    again = recorded / "again"
    assert crd(["export", str(recorded / "run"), "--format", "mcap", "--out", str(recorded / "exported.mcap")]) == 0
    assert crd(["run", str(recorded / "two.toml"), "--out", str(again), "--record", str(recorded / "again.mcap"),
                "--key-file", str(recorded / "secoc.key")]) == 0
    capsys.readouterr()
    data = (recorded / "run.mcap").read_bytes()
    assert (recorded / "exported.mcap").read_bytes() == data
    assert (recorded / "again.mcap").read_bytes() == data
    with open(recorded / "run.mcap", "rb") as handle:
        reader = make_reader(handle)
        stats = reader.get_summary().statistics
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
        attachments = {a.name: a for a in reader.iter_attachments()}
    assert stats.message_start_time == START_NS
    rows = _rows(recorded / "run")
    assert stats.message_end_time == _ns(rows[-1]["time_s"])
    assert "wall" not in json.dumps(metadata) and json.loads(metadata["crd"]["metrics"])["strategy"] == "none"
    assert attachments["config.resolved.toml"].data == (recorded / "run" / "config.resolved.toml").read_bytes()
    assert set(attachments) == {"config.resolved.toml", "active_safety.dbc"}


def test_the_default_file_and_the_errors(recorded, tmp_path, capsys):
    assert crd(["export", str(recorded / "run"), "--format", "mcap"]) == 0
    assert (recorded / "run" / "none" / "run.mcap").read_bytes() == (recorded / "run.mcap").read_bytes()
    assert crd(["export", str(tmp_path), "--format", "mcap"]) == 1
    assert "not a crd run directory" in capsys.readouterr().err
    assert crd(["export", str(recorded / "run"), "--format", "mcap", "--strategy", "tightening"]) == 1
    assert capsys.readouterr().err.strip() == f"error: {recorded / 'run'}: no run of strategy 'tightening' (it holds none)"


def test_record_without_the_extra_is_refused_before_the_run(recorded, tmp_path, monkeypatch, capsys):
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "rosbags" else real(name, *a))
    out = tmp_path / "never"
    assert crd(["run", str(recorded / "two.toml"), "--out", str(out), "--record", str(tmp_path / "x.mcap")]) == 1
    assert capsys.readouterr().err.strip().splitlines()[-1] == (
        "error: --record: the mcap format needs rosbags, which is not installed; install the extra: "
        "pip install 'crd[mcap]'")
    assert not out.exists()


# -- the Foxglove layout ---------------------------------------------------------------------------

LAYOUT_DIR = Path(__file__).resolve().parents[2] / "docs" / "foxglove"


def _layout_paths(node) -> list[str]:
    """Every message path in a layout: series values, x-axis paths, the log topic and 3D topics."""
    found = []
    if isinstance(node, dict):
        for key, value in node.items():
            if key in ("value", "topicToRender") and isinstance(value, str):
                found.append(value)
            elif key == "topics" and isinstance(value, dict):
                found += list(value)
            else:
                found += _layout_paths(value)
    elif isinstance(node, list):
        for item in node:
            found += _layout_paths(item)
    return found


def test_the_layout_file_is_what_its_script_writes():
    import runpy

    script = runpy.run_path(str(LAYOUT_DIR / "make_layout.py"))
    assert (LAYOUT_DIR / "crd-layout.json").read_text() == script["layout_text"]()


def test_every_path_of_the_layout_is_in_the_file(contents):
    """Each panel shows something: its topic exists and its field is a number or a name on the first message."""
    topics = contents[0]
    paths = _layout_paths(json.loads((LAYOUT_DIR / "crd-layout.json").read_text()))
    assert len(paths) >= 12
    for path in paths:
        topic, _, fields = path.partition(".")
        assert topic in topics, path
        value = topics[topic][0][1]
        for name in filter(None, fields.split(".")):
            value = getattr(value, name)
        assert not fields or isinstance(value, (int, float, str)), path  # a plottable number or a state name
        assert not isinstance(value, float) or math.isfinite(value), path
