"""Finding 4: one forged SimClock at 1000 s made every later input age negative, so nothing timed out.

Before issue 15: ``t=890 s with no input frame since t=0.1 s: mode STANDBY, fault flags 0``.
Now a SimClock must advance by 1..3 cycles (else it is rejected, counted and
flagged as ``FaultClock``), and an input stamped after the cycle time is a
``CLOCK`` fault in the core.
"""

import uuid

import can

from can_dbc import CounterSequence, encode
from ecu import EcuConfig, EcuNode
from ecu.core import FaultFlag, Mode


def _inputs(k, seq):
    frames = [encode("WheelSpeeds", {f"WheelSpeed{w}": 36.0 for w in ("FL", "FR", "RL", "RR")},
                     seq["WheelSpeeds"].next()),
              encode("DriverInput", {"AccelPedal": 20.0, "BrakePedal": 0.0,
                                     "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0},
                     seq["DriverInput"].next())]
    if k % 5 == 0:
        frames.append(encode("ObjectTrack", {"ObjectValid": 0, "ObjectRange": 0.0, "ObjectRangeRate": 0.0,
                                             "ObjectLateral": 0.0}, seq["ObjectTrack"].next()))
    return frames


def test_a_forged_future_sim_clock_cannot_stop_the_timeouts():
    bus = can.Bus(interface="virtual", channel=f"clk-{uuid.uuid4().hex[:8]}")
    try:
        node = EcuNode(bus, EcuConfig(sim_time=True))
        seq = {n: CounterSequence() for n in ("WheelSpeeds", "DriverInput", "ObjectTrack")}
        clock = CounterSequence()
        tick = lambda ms: node.on_sim_message(encode("SimClock", {"SimTimeMs": ms}, clock.next()))
        for k in range(30):
            for msg in _inputs(k, seq):
                node.on_sim_message(msg)
            tick(10 * k)
        assert node.mode == "STANDBY"
        for msg in _inputs(30, seq):
            node.on_sim_message(msg)
        tick(1_000_000)  # the forged clock, with the inputs of the cycle before it
        flags = 0
        for k in range(31, 200):  # clocks only: the inputs have stopped
            out = tick(10 * k)
            flags |= out.fault_flags if out is not None else 0
        assert node.mode == "FAULT"
        assert node.outputs.fault_flags & (1 << FaultFlag.WHEEL_SPEED_TIMEOUT)
        assert node.outputs.throttle_limit_pct == 0.0 and node.outputs.mode == Mode.FAULT
        assert flags & (1 << FaultFlag.CLOCK)
        assert node.stats["clock_errors"] == 1
    finally:
        bus.shutdown()
