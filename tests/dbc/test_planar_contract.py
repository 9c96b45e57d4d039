"""The planar part of the contract: the bus load the DBC states is the one its cycle times give;
the exports carry the new messages; a BLF of them decodes; the SI conversions round-trip."""

from __future__ import annotations

import math
import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from can_dbc import DBC_PATH, check_alone, encode
from can_dbc.bus_load import bus_load, frame_bits
from can_dbc.contract import enumeration
from can_dbc.planar import (TRACK_SLOTS, EscDynamics, Track, esc_dynamics, esc_signals, existence_class, track,
                             track_signals)
from cosim.cli.main import main
from tests.dbc.exported import assert_exported
from tests.dbc.test_decode_formats import write_log

PLANAR = ("SteeringOverride", "EscDynamics", *TRACK_SLOTS)
BEFORE = ("SafetyOverride", "WheelSpeeds", "DriverInput", "ObjectTrack", "EcuStatus", "EcuIdentity", "SimClock")


def _comment() -> str:
    return DBC_PATH.read_text(encoding="utf-8")


def _stated(after: str) -> tuple[float, float]:
    """The (nominal, worst-case) bus load in % that the DBC's comment states right after ``after``."""
    found = re.search(re.escape(after) + r" (\d+\.\d) % nominal, (\d+\.\d) % worst case", _comment())
    assert found, after
    return float(found.group(1)), float(found.group(2))


def test_frame_bits_match_the_textbook_figures():
    assert frame_bits(8, worst_case=False) == 111 and frame_bits(8, worst_case=True) == 135


@pytest.mark.parametrize("after, names", [("SimClock)", BEFORE), ("the whole contract", None)])
def test_the_dbc_states_the_bus_load_its_cycle_times_give(after, names):
    nominal, worst = _stated(after)
    assert round(100 * bus_load(names, worst_case=False), 1) == nominal
    assert round(100 * bus_load(names, worst_case=True), 1) == worst
    assert bus_load(worst_case=True) < 0.5


def test_the_stated_increments_add_up():
    text = _comment()
    assert "add 4.4 % (5.4 %) each" in text and "slots 7.1 % (8.6 %)" in text
    for name in ("EscDynamics", "SteeringOverride"):
        assert (round(100 * bus_load([name], worst_case=False), 1), round(100 * bus_load([name]), 1)) == (4.4, 5.4)
    tracks = list(TRACK_SLOTS)
    assert (round(100 * bus_load(tracks, worst_case=False), 1), round(100 * bus_load(tracks), 1)) == (7.1, 8.6)


@pytest.mark.parametrize("fmt", ["arxml", "kcd", "sym"])
def test_exports_carry_the_planar_messages(fmt, tmp_path):
    assert_exported(fmt, tmp_path, PLANAR, encode("RadarTrack5", track_signals(Track(3, 4, 6, 40.0, 2.5, -10.0, 0.5), 5), 7))


def test_a_blf_of_the_planar_frames_decodes(tmp_path, capsys):
    frames = [encode("SteeringOverride", {"SteerActive": 1, "SteerAngleRequest": -1.25}, 0),
              encode("EscDynamics", esc_signals(EscDynamics(-0.1, 3.0, -4.0)), 0),
              *(encode(name, track_signals(Track(slot, 1, 5, 10.0 + slot, -2.0, -1.0, 1.5), slot), 0)
                for name, slot in TRACK_SLOTS.items())]
    path = tmp_path / "planar.blf"
    write_log(path, frames)
    assert main(["dbc", "decode", str(path)]) == 0
    out = capsys.readouterr().out
    assert "SteeringOverride {'SteerActive': 1, 'SteerAngleRequest': -1.25}" in out
    assert "EscDynamics {" in out and "'LateralAccel': 3.0" in out
    for slot, name in enumerate(TRACK_SLOTS):
        assert f"{name} {{'Track{slot}Id': {slot}," in out
    assert f"{len(frames)} frames; rejected: {{}}" in out


finite = dict(allow_nan=False, allow_infinity=False)


_tracks = st.builds(Track, st.integers(0, 63), st.integers(0, 5), st.integers(1, 7), st.floats(0, 250, **finite),
                    st.floats(-32, 31.9, **finite), st.floats(-100, 100, **finite), st.floats(-16, 15.8, **finite))


@settings(max_examples=200, deadline=None)
@given(slot=st.integers(0, 7), sent=_tracks)
def test_tracks_round_trip_within_a_resolution(slot, sent):
    name = next(n for n, s in TRACK_SLOTS.items() if s == slot)
    got = track(check_alone(encode(name, track_signals(sent, slot), 3)).signals, slot)
    assert got[:3] == sent[:3]
    for a, b, step in zip(got[3:], sent[3:], (0.0625, 0.0625, 0.2, 0.125)):
        assert abs(a - b) <= step / 2 + 1e-9


@settings(max_examples=200, deadline=None)
@given(yaw=st.floats(-2.8, 2.8, **finite), ay=st.floats(-20, 20, **finite), ax=st.floats(-20, 20, **finite))
def test_esc_round_trips_within_a_resolution(yaw, ay, ax):
    got = esc_dynamics(check_alone(encode("EscDynamics", esc_signals(EscDynamics(yaw, ay, ax)), 1)).signals)
    assert abs(got.yaw_rate_rps - yaw) <= math.radians(0.005) + 1e-12
    assert abs(got.lat_accel_mps2 - ay) <= 0.005 + 1e-9 and abs(got.long_accel_mps2 - ax) <= 0.005 + 1e-9


def test_sensor_values_beyond_the_dbc_saturate_and_empty_slots_decode_as_none():
    esc = esc_dynamics(check_alone(encode("EscDynamics", esc_signals(EscDynamics(9.0, -35.0, math.nan)), 0)).signals)
    assert esc == pytest.approx(EscDynamics(math.radians(163.83), -20.48, -20.48))
    assert track(check_alone(encode("RadarTrack0", track_signals(None, 0), 0)).signals, 0) is None


def test_existence_probabilities_map_onto_the_dbc_classes():
    names = enumeration("RadarTrack0", "Track0Existence")
    cases = {0.0: "NO_TRACK", 0.1: "BELOW_25_PCT", 0.25: "BELOW_50_PCT", 0.5: "BELOW_75_PCT",
             0.875: "BELOW_90_PCT", 0.9: "BELOW_99_PCT", 0.995: "BELOW_99_9_PCT", 0.999: "UP_TO_100_PCT",
             1.0: "UP_TO_100_PCT"}
    assert {p: names[existence_class(p)] for p in cases} == cases
