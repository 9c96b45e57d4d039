"""The rear corner radars' frames CornerTrack0..3: the forward slots' layout with a signed PosX (beside and behind
the car), E2E-protected like every input, carried by the ARXML/KCD/SYM exports and decoded from a log."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from can_dbc import DATABASE, FrameError, check_alone, encode
from can_dbc.bus_load import bus_load
from can_dbc.planar import CORNER_SLOTS, TRACK_SLOTS, Track, track, track_signals
from cosim.cli.main import main
from tests.dbc.exported import assert_exported
from tests.dbc.test_decode_formats import write_log

BESIDE = Track(5, 4, 7, -2.5, 2.625, 0.2, -0.5)


def test_four_slots_after_the_forward_ones_each_an_id_of_its_own():
    assert dict(CORNER_SLOTS) == {f"CornerTrack{k}": len(TRACK_SLOTS) + k for k in range(4)}
    assert [DATABASE.get_message_by_name(n).frame_id for n in CORNER_SLOTS] == [0x0D2, 0x0D4, 0x0D6, 0x0D8]
    pos_x = DATABASE.get_message_by_name("CornerTrack0").get_signal_by_name("Corner0PosX")
    assert (pos_x.minimum, pos_x.maximum, pos_x.is_signed) == (-128.0, 127.9375, True)
    slots = list(CORNER_SLOTS)
    assert (round(100 * bus_load(slots, worst_case=False), 1), round(100 * bus_load(slots), 1)) \
        == (3.6, 4.3)


_tracks = st.builds(Track, st.integers(0, 63), st.integers(0, 5), st.integers(1, 7),
                    st.floats(-128, 127.9, allow_nan=False), st.floats(-32, 31.9, allow_nan=False),
                    st.floats(-100, 100, allow_nan=False), st.floats(-16, 15.8, allow_nan=False))


@settings(max_examples=200, deadline=None)
@given(k=st.integers(0, 3), sent=_tracks)
def test_corner_tracks_round_trip_within_a_resolution(k, sent):
    slot = len(TRACK_SLOTS) + k
    got = track(check_alone(encode(f"CornerTrack{k}", track_signals(sent, slot), 3)).signals, slot)
    assert got[:3] == sent[:3]
    for a, b, step in zip(got[3:], sent[3:], (0.0625, 0.0625, 0.2, 0.125)):
        assert abs(a - b) <= step / 2 + 1e-9


def test_a_forged_or_corrupted_corner_frame_fails_its_e2e_check():
    msg = encode("CornerTrack1", track_signals(BESIDE, 9), 4)
    assert track(check_alone(msg).signals, 9) == BESIDE
    corrupted = bytearray(msg.data)
    corrupted[3] ^= 0x10  # PosX changed on the wire, CRC kept
    with pytest.raises(FrameError):
        check_alone(type(msg)(arbitration_id=msg.arbitration_id, data=corrupted, is_extended_id=False))
    # the same payload under another slot's ID: the data ID (the frame ID) is in the CRC
    with pytest.raises(FrameError):
        check_alone(type(msg)(arbitration_id=0x0D6, data=msg.data, is_extended_id=False))


@pytest.mark.parametrize("fmt", ["arxml", "kcd", "sym"])
def test_exports_carry_the_corner_messages(fmt, tmp_path):
    assert_exported(fmt, tmp_path, CORNER_SLOTS, encode("CornerTrack2", track_signals(BESIDE, 10), 7))


def test_a_blf_of_the_corner_frames_decodes(tmp_path, capsys):
    frames = [encode(name, track_signals(BESIDE, slot), 0) for name, slot in CORNER_SLOTS.items()]
    path = tmp_path / "corner.blf"
    write_log(path, frames)
    assert main(["dbc", "decode", str(path)]) == 0
    out = capsys.readouterr().out
    for k, name in enumerate(CORNER_SLOTS):
        assert f"{name} {{'Corner{k}Id': 5," in out and f"'Corner{k}PosX': -2.5" in out
    assert f"{len(frames)} frames; rejected: {{}}" in out
