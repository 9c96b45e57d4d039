"""The ECU node in this process, stepped by the master: the reference link.

Two python-can buses join one channel unique to the run: the master's and
the node's. The interface is ``crd_inproc`` (ours: no copies, no locks) by
default, or any in-process python-can interface such as ``virtual``; the
outputs are identical either way (``tests/cosim/test_golden_paper.py``).
"""

from __future__ import annotations

import itertools
import os

import can

from ecu import EcuConfig, EcuNode

from ..results.run_record import RunEvent
from .ecu_link import LinkReport

_channels = itertools.count()


class InProcessLink:
    """An :class:`~cosim.link.ecu_link.EcuLink`: the node runs one cycle inside :meth:`send`."""

    realtime = False

    def __init__(self, config: EcuConfig, interface: str = "crd_inproc") -> None:
        channel = f"crd-{os.getpid()}-{next(_channels)}"
        self._bus = can.Bus(interface=interface, channel=channel, receive_own_messages=False)
        try:
            self._ecu_bus = can.Bus(interface=interface, channel=channel, receive_own_messages=False)
        except BaseException:
            self._bus.shutdown()
            raise
        self.node = EcuNode(self._ecu_bus, config)
        self.events: list[RunEvent] = []
        # bound once: the master calls these every cycle (saves an attribute chain per call)
        self._send_frame, self._recv_frame, self._step = self._bus.send, self._bus.recv, self.node.step

    def start(self) -> None:
        pass

    def pace(self, cycle: int) -> None:
        pass

    def send(self, t_s: float, cycle: int, frames: list[can.Message]) -> list[can.Message]:
        """Send ``frames`` and run one ECU cycle; returns the extra frames sent (none here)."""
        send = self._send_frame
        for msg in frames:
            send(msg)
        self._step(t_s)
        return []

    def collect(self, t_s: float, cycle: int) -> list[can.Message]:
        """The ECU's frames of this cycle."""
        recv = self._recv_frame
        received = []
        while (msg := recv(0.0)) is not None:
            received.append(msg)
        return received

    def report(self) -> LinkReport:
        return LinkReport()

    def time_phases(self, timed) -> None:
        """Profiling only: charge the node's cycle to the ``ecu`` phase (see :mod:`cosim.loop.phase_timer`)."""
        self._step = timed("ecu", self._step)

    def close(self) -> None:
        self._ecu_bus.shutdown()
        self._bus.shutdown()
