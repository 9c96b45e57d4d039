"""crd_inproc: the in-process python-can interface (one deque per receiver, no copies)."""

from __future__ import annotations

import threading
import time

import can
import pytest


@pytest.fixture
def pair():
    channel = f"t-{time.monotonic_ns()}"
    a = can.Bus(interface="crd_inproc", channel=channel)
    b = can.Bus(interface="crd_inproc", channel=channel)
    yield a, b
    a.shutdown()
    b.shutdown()


def _msg(i: int) -> can.Message:
    return can.Message(arbitration_id=i, is_extended_id=False, data=bytes([i & 0xFF] * 8))


def test_frames_reach_every_other_bus_in_order_and_uncopied(pair):
    a, b = pair
    c = can.Bus(interface="crd_inproc", channel=a.channel_info.split("'")[1])
    try:
        sent = [_msg(i) for i in range(5)]
        for m in sent:
            a.send(m)
        for rx in (b, c):
            got = [rx.recv(0.0) for _ in range(5)]
            assert all(g is s for g, s in zip(got, sent))  # the same immutable message, no deep copy
            assert rx.recv(0.0) is None
        assert a.recv(0.0) is None  # not its own frames
    finally:
        c.shutdown()


def test_own_messages_on_request_and_filters(pair):
    a, b = pair
    own = can.Bus(interface="crd_inproc", channel="own-" + str(time.monotonic_ns()), receive_own_messages=True)
    try:
        own.send(_msg(1))
        assert own.recv(0.0).arbitration_id == 1
    finally:
        own.shutdown()
    b.set_filters([{"can_id": 0x2, "can_mask": 0x7FF}])
    a.send(_msg(1))
    a.send(_msg(2))
    assert b.recv(0.5).arbitration_id == 2  # BusABC.recv skips the filtered frame within the timeout
    assert b.recv(0.0) is None


def test_blocking_receive_wakes_on_a_frame_and_times_out(pair):
    a, b = pair
    timer = threading.Timer(0.05, lambda: a.send(_msg(7)))
    timer.start()
    try:
        assert b.recv(timeout=5.0).arbitration_id == 7  # a condition wait, not a sleep
    finally:
        timer.cancel()
    t0 = time.monotonic()
    assert b.recv(timeout=0.02) is None
    assert time.monotonic() - t0 >= 0.015


def test_shutdown_is_idempotent_and_a_closed_bus_refuses(pair):
    a, b = pair
    a.shutdown()
    a.shutdown()
    with pytest.raises(can.CanOperationError):
        a.send(_msg(1))
    b.send(_msg(1))  # b's only peer left: nothing to deliver, no error
    assert b.recv(0.0) is None


def test_send_all_delivers_like_send_in_order(pair):
    a, b = pair
    c = can.Bus(interface="crd_inproc", channel=a.channel_info.split("'")[1])
    try:
        sent = [_msg(i) for i in range(4)]
        a.send_all(sent)
        a.send(_msg(9))
        for rx in (b, c):
            got = [rx.recv(0.0) for _ in range(5)]
            assert all(g is s for g, s in zip(got, sent)) and got[4].arbitration_id == 9
            assert rx.recv(0.0) is None
        assert a.recv(0.0) is None  # not its own frames
        timer = threading.Timer(0.05, lambda: a.send_all([_msg(7)]))
        timer.start()
        try:
            assert b.recv(timeout=5.0).arbitration_id == 7  # wakes a blocked receiver, as send does
        finally:
            timer.cancel()
    finally:
        c.shutdown()
    a.shutdown()
    with pytest.raises(can.CanOperationError):
        a.send_all([_msg(1)])
