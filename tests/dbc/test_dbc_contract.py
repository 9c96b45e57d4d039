"""The DBC itself: IDs, nodes, cycle times, units, and a second parser."""

import pytest

from can_dbc import AUTHENTICATORS, DATABASE, DBC_PATH, LAYOUTS

EXPECTED = {
    "SafetyOverride": (0x090, "ECU", 10),
    "WheelSpeeds": (0x0A0, "ESC", 10),
    "DriverInput": (0x0B0, "DRIVER", 10),
    "ObjectTrack": (0x0C0, "RADAR", 50),
    "EcuStatus": (0x3A0, "ECU", 100),
    "EcuRegionStatus": (0x3A8, "ECU", 100),
    "EcuIdentity": (0x3B0, "ECU", 1000),
    "SimClock": (0x7F0, "SIM", 10),
    "SteeringOverride": (0x094, "ECU", 10),
    "EscDynamics": (0x0A8, "ESC", 10),
    **{f"RadarTrack{k}": (0x0C2 + 2 * k, "RADAR", 50) for k in range(8)},
    **{f"CornerTrack{k}": (0x0D2 + 2 * k, "RADAR", 50) for k in range(4)},
}


def test_messages_ids_senders_cycles():
    assert set(LAYOUTS) == set(EXPECTED)
    for name, (frame_id, sender, cycle) in EXPECTED.items():
        message = DATABASE.get_message_by_name(name)
        assert message.frame_id == frame_id
        assert message.senders == [sender]
        assert message.cycle_time == cycle
        assert message.length == 8 and not message.is_extended_frame


def test_nodes():
    assert {node.name for node in DATABASE.nodes} == {"ECU", "ESC", "EPS", "DRIVER", "RADAR", "SIM"}


def test_enumerations_declared():
    mode = DATABASE.get_message_by_name("SafetyOverride").get_signal_by_name("Mode")
    assert {int(k): str(v) for k, v in mode.choices.items()} == {
        0: "STANDBY", 1: "TIGHTENING", 2: "CONTINGENCY", 3: "FAULT"}
    strategy = DATABASE.get_message_by_name("EcuStatus").get_signal_by_name("Strategy")
    assert {int(k): str(v) for k, v in strategy.choices.items()} == {
        0: "NONE", 1: "CONSERVATIVE", 2: "TIGHTENING", 3: "ADAPTIVE"}


def test_physical_signals_declare_units():
    units = {s.name: s.unit for layout in LAYOUTS.values() for s in layout.signals}
    assert units["WheelSpeedFL"] == "km/h"
    assert units["BrakeDecelRequest"] == "m/s^2"
    assert units["ObjectRange"] == "m"
    assert units["SimTimeMs"] == "ms"
    assert units["AccelPedal"] == "%"
    assert units["YawRate"] == units["SteeringWheelRate"] == "deg/s"
    assert units["SteerAngleRequest"] == units["SteeringWheelAngle"] == "deg"
    assert units["Track7PosY"] == "m" and units["Track7VelY"] == "m/s"


def test_e2e_header_layout():
    for message in DATABASE.messages:
        if message.frame_id in AUTHENTICATORS.values():
            continue  # SecOC authenticators carry Freshness and Mac instead (test below)
        crc, counter = message.signals[0], message.signals[1]
        assert (crc.name, crc.start, crc.length) == (f"{message.name}_CRC", 0, 8)
        assert (counter.name, counter.start, counter.length, counter.maximum) == (f"{message.name}_Counter", 8, 4, 14)


def test_secoc_authenticators():
    """Each protected message has an authenticator at ID + 1: 16-bit freshness, 48-bit MAC, same cycle."""
    assert set(AUTHENTICATORS) == set(EXPECTED) - {"EcuStatus", "EcuRegionStatus"}
    for name, auth_id in AUTHENTICATORS.items():
        protected = DATABASE.get_message_by_name(name)
        auth = DATABASE.get_message_by_frame_id(auth_id)
        assert auth_id == protected.frame_id + 1 and auth.name == name + "Auth"
        assert auth.senders == protected.senders and auth.cycle_time == protected.cycle_time
        assert [(s.name, s.start, s.length) for s in auth.signals] == [
            (f"{name}Auth_Freshness", 0, 16), (f"{name}Auth_Mac", 16, 48)]


def test_canmatrix_loads_the_dbc():
    canmatrix_formats = pytest.importorskip("canmatrix.formats", reason="canmatrix is a test dependency")
    matrices = canmatrix_formats.loadp(str(DBC_PATH))
    matrix = next(iter(matrices.values()))
    frames = {frame.name: frame for frame in matrix.frames}
    assert set(frames) == set(EXPECTED) | {name + "Auth" for name in AUTHENTICATORS}
    assert frames["ObjectTrack"].arbitration_id.id == 0x0C0
    assert frames["ObjectTrack"].size == 8
    assert {s.name for s in frames["WheelSpeeds"].signals} >= {"WheelSpeedFL", "WheelSpeedRR"}
