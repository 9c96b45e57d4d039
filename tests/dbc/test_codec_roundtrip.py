"""Every message round-trips at its min, max and mid values; encode is strict."""

import math

import pytest

import can_dbc
from can_dbc import LAYOUTS, Receiver, SignalError, encode


def _values(layout, which):
    out = {}
    for sig in layout.signals:
        if sig.choices:
            ordered = sorted(sig.choices)
            raw = {"min": ordered[0], "max": ordered[-1], "mid": ordered[len(ordered) // 2]}[which]
        else:
            raw = {"min": sig.raw_min, "max": sig.raw_max, "mid": (sig.raw_min + sig.raw_max) // 2}[which]
        out[sig.name] = raw * sig.scale + sig.offset
    return out


@pytest.mark.parametrize("which", ["min", "max", "mid"])
@pytest.mark.parametrize("name", sorted(LAYOUTS))
def test_roundtrip(name, which):
    values = _values(LAYOUTS[name], which)
    msg = encode(name, values, counter=7)
    assert msg.arbitration_id == LAYOUTS[name].frame_id
    assert msg.dlc == 8 and not msg.is_extended_id
    frame = Receiver().check(msg)
    assert frame.name == name and frame.counter == 7 and frame.fresh
    for key, value in values.items():
        assert math.isclose(frame.signals[key], value, rel_tol=0, abs_tol=1e-9), key
    # An independent decoder (cantools) agrees on every value and on the E2E header.
    decoded = can_dbc.DATABASE.decode_message(msg.arbitration_id, msg.data, decode_choices=False)
    crc_name, counter_name = can_dbc.e2e_signal_names(name)
    assert decoded[counter_name] == 7
    assert decoded[crc_name] == can_dbc.e2e_p01_crc(msg.arbitration_id, msg.data)
    for key, value in values.items():
        assert math.isclose(decoded[key], value, abs_tol=1e-9), key


def test_mins_and_maxes_are_the_contract():
    layout = LAYOUTS["ObjectTrack"]
    ranges = {s.name: (s.minimum, s.maximum, s.scale) for s in layout.signals}
    assert ranges["ObjectRange"] == (0.0, 250.0, 0.02)
    assert ranges["ObjectRangeRate"] == (-100.0, 100.0, 0.02)
    assert LAYOUTS["SimClock"].signals[0].maximum == 2**32 - 1


def test_missing_signal_raises():
    with pytest.raises(SignalError, match="missing signal BrakePedal"):
        encode("DriverInput", {"AccelPedal": 1.0, "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}, 0)


def test_out_of_range_raises_with_expected_and_actual():
    with pytest.raises(SignalError, match=r"expected 0.0..100.0 %, got 100.5"):
        encode("DriverInput", {"AccelPedal": 100.5, "BrakePedal": 0.0,
                               "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}, 0)


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_non_finite_raises(bad):
    with pytest.raises(SignalError, match="finite"):
        encode("DriverInput", {"AccelPedal": bad, "BrakePedal": 0.0,
                               "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}, 0)


def test_unknown_signal_and_message_raise():
    with pytest.raises(SignalError, match="unknown signals"):
        encode("DriverInput", {"AccelPedal": 1.0, "BrakePedal": 0.0, "Steer": 0.0}, 0)
    with pytest.raises(SignalError, match="unknown message"):
        encode("NoSuchMessage", {}, 0)


@pytest.mark.parametrize("counter", [-1, 15, 16, 1.0])
def test_counter_outside_0_14_raises(counter):
    with pytest.raises(SignalError, match="counter"):
        encode("SimClock", {"SimTimeMs": 0}, counter)


def test_undefined_enum_cannot_be_encoded_past_range():
    with pytest.raises(SignalError):
        encode("EcuStatus", {"Strategy": 4, "Proximity": 0, "StoppingDistance": 0,
                             "SpeedEstimate": 0, "FaultWheelSpeedTimeout": 0,
                             "FaultDriverInputTimeout": 0, "FaultObjectTimeout": 0, "FaultE2E": 0,
                             "FaultInternal": 0}, 0)
