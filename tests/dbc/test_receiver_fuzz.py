"""Hypothesis fuzzing of the receiver: only FrameError escapes, and nothing with a
wrong CRC or counter is ever accepted."""

import can
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from can_dbc import LAYOUTS_BY_ID, FrameError, Receiver, e2e_p01_crc

FUZZ = settings(max_examples=10_000, deadline=None, suppress_health_check=[HealthCheck.too_slow])
contract_ids = st.sampled_from(sorted(LAYOUTS_BY_ID))
any_ids = st.one_of(contract_ids, st.integers(0, 0x7FF), st.integers(0, 0x1FFFFFFF))


@st.composite
def frames(draw):
    arbitration_id = draw(any_ids)
    data = draw(st.binary(min_size=0, max_size=8))
    extended = draw(st.booleans()) if arbitration_id <= 0x7FF else True
    if draw(st.booleans()) and len(data) == 8:  # half the time, a valid CRC
        data = bytearray(data)
        data[0] = e2e_p01_crc(arbitration_id, data)
        data = bytes(data)
    return can.Message(arbitration_id=arbitration_id, is_extended_id=extended, data=data)


@FUZZ
@given(st.lists(frames(), min_size=1, max_size=6))
def test_receiver_raises_only_frame_errors_and_rejects_bad_e2e(sequence):
    rx = Receiver()
    last_counter = {}
    for msg in sequence:
        layout = LAYOUTS_BY_ID.get(msg.arbitration_id)
        try:
            frame = rx.check(msg)
        except FrameError:
            if layout is not None and not msg.is_extended_id and len(msg.data) == 8 \
                    and msg.data[0] == e2e_p01_crc(msg.arbitration_id, msg.data) and msg.data[1] & 0x0F <= 14:
                # a rejected jump still resynchronises the receiver to the new counter (documented)
                last_counter[layout.name] = msg.data[1] & 0x0F
            continue
        # Accepted: it must be a contract frame with an exact CRC and a plausible counter.
        assert layout is not None and not msg.is_extended_id and len(msg.data) == 8
        assert msg.data[0] == e2e_p01_crc(msg.arbitration_id, msg.data)
        counter = msg.data[1] & 0x0F
        assert counter <= 14
        previous = last_counter.get(layout.name)
        if previous is not None:
            assert (counter - previous) % 15 <= 2
        last_counter[layout.name] = counter
        assert frame.counter == counter


@FUZZ
@given(frames())
def test_receive_never_raises(msg):
    rx = Receiver()
    rx.receive(msg)
    assert sum(rx.stats.values()) == 1
