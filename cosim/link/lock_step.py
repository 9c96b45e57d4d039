"""Lock-step with an ECU on a bus: each cycle one round trip, the ECU cycling on ``SimClock``.

Each cycle the master sends its frames, then ``SimClock`` (``SimTimeMs =
round(t * 1000)``); the ECU (``crd ecu --sim-time``) runs one cycle on it,
after the frames before it, and the master waits up to ``stall_timeout_s``
(wall time) for that cycle's ``SafetyOverride`` (and ``SteeringOverride`` from an
ECU with steering authority, :mod:`ecu.equipment`; and the ``EcuStatus`` due in that cycle,
which the ECU sends after ``EcuRegionStatus``, whose values go into the time series) before it
advances. The ECU sees the same
frames at the same cycle times as in process, so metrics and time series are
identical. A silent ECU is a stall (:mod:`cosim.link.stall`): simulated time
is held while the master waits; past ``stall_timeout_s`` it stops the run with
:class:`~cosim.errors.EcuStallError`; a wait over ``reply_timeout_s`` is
recorded as an ``ecu_stall`` event.
"""

from __future__ import annotations

import time

import can

from can_dbc import AUTHENTICATORS, LAYOUTS, CounterSequence, SecOcSender, encode
from ecu import EcuConfig
from ecu.equipment import EQUIPMENT

from .bus_link import BusLink
from .ecu_link import EcuOptions, LinkReport
from .stall import StallWatch

STATUS_ID = LAYOUTS["EcuStatus"].frame_id


def reply_ids(equipment: str, keyed: bool) -> frozenset[int]:
    """The frames of a cycle's reply: the requests the ECU's equipment sends every cycle (``SafetyOverride``,
    and ``SteeringOverride`` with steering authority), and with a key their authenticators. The reply is
    complete with all of them (the steering gateway counts SteeringOverride frames per cycle, so one must not
    slip into the next cycle's collection)."""
    names = EQUIPMENT[equipment].requests
    ids = frozenset(LAYOUTS[name].frame_id for name in names)
    return ids | frozenset(AUTHENTICATORS[name] for name in names) if keyed else ids


class LockStepLink(BusLink):
    """An :class:`~cosim.link.ecu_link.EcuLink` over a bus in simulated time (process or attach)."""

    realtime = False

    def __init__(self, options: EcuOptions, config: EcuConfig, key: bytes | None = None) -> None:
        super().__init__(options, config, key)
        self._signer = SecOcSender(key) if key is not None else None
        self._status_period = config.status_period_cycles  # the statuses of the cycle, in this cycle
        self._reply_ids = reply_ids(config.equipment, key is not None)
        self._clock_seq = CounterSequence()
        self._stall = StallWatch(options.reply_timeout_s, options.stall_timeout_s)

    def start(self) -> None:
        """Wait for the ECU to join and to announce that it waits for a run, with settings that fit. An ECU that
        runs its own settings (``--ecu-settings``) replies with its own equipment's requests, where known."""
        self._join(first_frame_joins=False)
        own = (self._ecu_settings or {}).get("settings") or {}
        if own.get("equipment") in EQUIPMENT:
            self._reply_ids = reply_ids(own["equipment"], self._signer is not None)

    def pace(self, cycle: int) -> None:
        pass

    def send(self, t_s: float, cycle: int, frames: list[can.Message]) -> list[can.Message]:
        """Send ``frames``, then ``SimClock`` (and its authenticator), in one batch; returns what it added."""
        clock = encode("SimClock", {"SimTimeMs": int(round(t_s * 1000.0))}, self._clock_seq.next())
        added = [clock] if self._signer is None else [clock, self._signer.authenticator(clock)]
        self.endpoint.send_all([*frames, *added], t_s)  # SecOC: the clock's authenticator right after it
        return added

    def collect(self, t_s: float, cycle: int) -> list[can.Message]:
        """Wait (bounded) for this cycle's reply, then take anything else already there."""
        endpoint, received = self.endpoint, []
        if endpoint.lost:
            return endpoint.drain(t_s, received)
        wanted = set(self._reply_ids)
        if self._status_period is not None and cycle % self._status_period == 0:
            wanted.add(STATUS_ID)
        # without a peer count the first reply wait is the join wait
        first = cycle == 0 and endpoint.peers is None
        wait_s = self.options.join_timeout_s if first else self.options.stall_timeout_s
        started = time.monotonic()
        deadline = started + wait_s
        while wanted and not endpoint.lost:
            remaining = deadline - time.monotonic()
            if remaining <= 0.0:
                raise self._stall.expired(t_s, time.monotonic() - started, endpoint.who())
            msg = endpoint.recv(remaining, t_s)
            if msg is not None:
                received.append(msg)
                wanted.discard(msg.arbitration_id)
        if not first:
            self._stall.waited(t_s, time.monotonic() - started, endpoint.events)
        return endpoint.drain(t_s, received)  # e.g. a second ECU's frames

    def report(self) -> LinkReport:
        return LinkReport(ecu_report=self.endpoint.ecu_report, join_wait_s=self.endpoint.join_wait_s,
                          ecu_settings=self._ecu_settings)
