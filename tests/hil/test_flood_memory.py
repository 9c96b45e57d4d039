"""Finding 5 of issue 15: a flood between two SimClock frames must not grow the ECU's memory.

``crd ecu --sim-time`` kept every frame received before the next ``SimClock``
(one ``can.Message`` each): a 12 k/s flood grew it from 32 to 219 MB in 60 s.
Here 30,000 valid frames (2.5 s of that flood) arrive with no ``SimClock``; the
node may keep only the latest checked frame of each message. Counted with
``tracemalloc``, so the test does not depend on timing or on the allocator.
The 60 s RSS figure is ``python benchmarks/bench_hil.py --flood-s 60``.
"""

from __future__ import annotations

import tracemalloc

import can

from can_dbc import CounterSequence, encode
from ecu import EcuConfig, EcuNode

from .inputs import wheels

FLOOD_FRAMES = 30_000
#: what a node may allocate for a flood of any length (bytes): far below one kept frame each
BOUND_BYTES = 1_000_000


def test_a_flood_without_simclock_keeps_only_the_latest_frame_of_each_message() -> None:
    with can.Bus(interface="virtual", channel="flood-memory") as bus:
        node = EcuNode(bus, EcuConfig(sim_time=True))
        counters, clock = CounterSequence(), CounterSequence()
        # 60 frames: a whole number of counter cycles (15), so the repeated pattern stays in sequence
        flood = [encode("WheelSpeeds", wheels(20.0 + i % 7), counters.next()) for i in range(60)]
        tracemalloc.start()
        try:
            before = tracemalloc.take_snapshot()
            for i in range(FLOOD_FRAMES):
                frame = flood[i % 60]  # a bus delivers a new message object for every frame
                node.on_sim_message(can.Message(arbitration_id=frame.arbitration_id, data=frame.data,
                                                is_extended_id=False, check=False))
            grown = sum(s.size_diff for s in tracemalloc.take_snapshot().compare_to(before, "filename"))
        finally:
            tracemalloc.stop()
        assert grown < BOUND_BYTES, f"{FLOOD_FRAMES} flood frames grew the node by {grown / 1e6:.1f} MB"
        # the flood still counts as received input: the next cycle sees the latest wheel speed
        node.on_sim_message(encode("SimClock", {"SimTimeMs": 10}, clock.next()))
        assert node.cycles == 1
        assert node.stats["good"] == FLOOD_FRAMES + 1  # every flood frame was checked and good, and the clock
        assert node.outputs is not None and node.state.speed_mps > 0.0
