"""How the co-simulation reaches the ECU: the :class:`EcuLink` protocol, its options, and the choice.

:class:`EcuOptions` (``crd run/paper --ecu inprocess|process|attach``):

* ``inprocess`` (default): an :class:`ecu.EcuNode` on an in-process bus,
  stepped by the master (:mod:`cosim.link.in_process`); the bus is our lean
  ``crd_inproc`` unless ``--bus-interface virtual`` asks for python-can's;
* ``process``: the master opens the bus first (``crd_pair`` in lock-step:
  point to point, it listens; ``crd_unix`` in real time: it hosts the hub),
  spawns ``crd ecu`` (:mod:`cosim.link.ecu_process`), waits up to
  ``join_timeout_s`` for it to join, and stops it by PID at the end;
* ``attach``: an ECU already running on ``interface``/``channel``; the
  master waits up to ``join_timeout_s`` for it.

An ECU on a bus (``process``, ``attach``) announces what it runs; before the
first cycle the link checks it against the scenario's ``[ecu]``
(``ecu_settings``, :mod:`cosim.link.ecu_identity`) and reports it.

Over a bus the master either runs in lock-step (:mod:`cosim.link.lock_step`:
each cycle's frames, then ``SimClock``, then a bounded wait for the reply) or
in real time (:mod:`cosim.link.real_time`: paced to the wall clock, taking
whatever the ECU sent). Both share :class:`cosim.link.bus_endpoint.BusEndpoint`
(the bus, the spawned process, joining, bus errors and ``ecu_lost``).

Authentication (issue 15, :mod:`can_dbc.secoc`): :func:`run_key` picks the
run's SecOC key: ``key_file`` (``--key-file``) or the ECU config's
``key_file``; otherwise, in process and for a spawned ECU, a fresh random key
per run (written, mode 0600, into the run's private 0700 directory for the
child); ``attach`` without a key file, or ``authenticate=False``, runs with
E2E protection only. The master then sends each input and ``SimClock`` with
its authenticator frame, and waits for ``SafetyOverride``'s authenticator too.

ECU lost (a bus error after which the spawned process is dead or no peer is
left; in real time also no frame for ``reply_timeout_s``): the gateway falls
back to the driver, and the run exits 4 unless ``[checks] expect_events``
lists ``ecu_lost``. An ECU that is there but silent in lock-step is a stall
(:mod:`cosim.link.stall`): the master waits up to ``stall_timeout_s`` with
simulated time held, then stops the run with an error. Events are
rate-limited (:class:`cosim.results.events.EventLog`): a dead peer fails every
frame, and only the first few ``bus_error`` events and a count are kept.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import can

from can_dbc import generate_key, load_key_file
from ecu import EcuConfig

from ..errors import CosimError
from ..results.run_record import RunEvent
from .stall import DEFAULT_STALL_TIMEOUT_S

ECU_MODES = ("inprocess", "process", "attach")


class EcuLinkError(CosimError, RuntimeError):
    """The out-of-process ECU could not be reached (did not join in time, or exited at start)."""


@dataclass(frozen=True, slots=True)
class LinkReport:
    """What a link tells the run record when it is closed."""

    timing: dict[str, float] = field(default_factory=dict)  # real time: the master's lag and jitter (s)
    ecu_report: str = ""  # what a spawned crd ecu printed (its run summary)
    join_wait_s: float = 0.0  # wall time spent waiting for an out-of-process ECU to join
    #: an ECU on a bus: what it announced it runs (cosim.link.ecu_identity.IdentityCheck.record)
    ecu_settings: dict | None = None


class EcuLink(Protocol):
    """The master's view of the ECU, whatever its placement. Frames are ``can.Message``s in both directions."""

    realtime: bool
    events: list[RunEvent]

    def start(self) -> None:
        """Before the first cycle: wait (bounded) for the ECU to be there."""

    def pace(self, cycle: int) -> None:
        """Real time: wait for cycle ``cycle``'s wall-clock deadline; otherwise return at once."""

    def send(self, t_s: float, cycle: int, frames: list[can.Message]) -> list[can.Message]:
        """Deliver this cycle's frames to the ECU (in process: and run its cycle); returns extra frames sent."""

    def collect(self, t_s: float, cycle: int) -> list[can.Message]:
        """The ECU's frames of this cycle."""

    def report(self) -> LinkReport:
        """Timing and the ECU process's own report, after :meth:`close`."""

    def close(self) -> None:
        """Stop what the link started and leave the bus; idempotent."""


@dataclass(frozen=True, slots=True)
class EcuOptions:
    """Where the ECU runs and how the master talks to it (times in wall-clock s)."""

    mode: str = "inprocess"
    #: python-can interface; None: ``crd_inproc`` in process, ``crd_pair`` for a spawned ECU in
    #: lock-step, else ``crd_unix``
    interface: str | None = None
    channel: str | None = None  # process: a fresh socket in a private temp dir when None
    realtime: bool = False
    join_timeout_s: float = 10.0
    reply_timeout_s: float = 1.0
    stop_timeout_s: float = 5.0
    #: SecOC key file shared with the ECU; None: the ECU config's, else a fresh key (see run_key)
    key_file: str | None = None
    #: False: E2E protection only (no SecOC), unless a key file is named
    authenticate: bool = True
    stall_timeout_s: float = DEFAULT_STALL_TIMEOUT_S  # lock-step: longest wait for one cycle's reply
    #: lock-step with a spawned ECU: start the next run's ECU process once this run's has joined
    #: (:func:`~cosim.link.ecu_process.prepare_spare`); False for a run that no other follows
    spare: bool = True
    #: whose settings an ECU on a bus runs with: ``scenario`` (checked against its announcement),
    #: ``ecu`` (whatever it runs, recorded) or the path of its settings file (:mod:`cosim.link.ecu_identity`)
    ecu_settings: str = "scenario"

    def __post_init__(self) -> None:
        if self.interface is None:
            object.__setattr__(self, "interface", _default_interface(self.mode, self.realtime))
        if self.mode not in ECU_MODES:
            raise EcuLinkError(f"ecu mode: expected one of {list(ECU_MODES)}, got {self.mode!r}")
        if self.mode == "attach" and not self.channel:
            raise EcuLinkError("ecu mode 'attach': expected the channel of the running ECU's bus, got none")
        if self.realtime and self.mode == "inprocess":
            raise EcuLinkError("--realtime: expected --ecu process or attach (an ECU on its own clock), "
                               "got inprocess")
        if self.mode == "inprocess" and self.ecu_settings != "scenario":
            raise EcuLinkError(f"--ecu-settings {self.ecu_settings}: expected --ecu attach or process (an ECU in "
                               "this process is built from the scenario's [ecu])")
        for name in ("join_timeout_s", "reply_timeout_s", "stop_timeout_s", "stall_timeout_s"):
            if not getattr(self, name) > 0.0:
                raise EcuLinkError(f"{name}: expected > 0 s, got {getattr(self, name)!r}")


def run_key(options: EcuOptions, config: EcuConfig) -> bytes | None:
    """The run's SecOC key: a named key file, else a fresh one in process or for a spawned ECU, else None."""
    key_file = options.key_file or config.key_file
    if key_file:
        return load_key_file(key_file)
    if options.authenticate and options.mode in ("inprocess", "process"):
        return generate_key()
    return None


def _default_interface(mode: str, realtime: bool) -> str:
    if mode == "inprocess":
        return "crd_inproc"
    return "crd_pair" if mode == "process" and not realtime else "crd_unix"


def open_link(options: EcuOptions, config: EcuConfig, cycle_s: float, key: bytes | None = None) -> EcuLink:
    """The link for ``options``: in process, lock-step over a bus, or real time over a bus
    (``key``: the run's SecOC key, see :func:`run_key`)."""
    if options.mode == "inprocess":
        from .in_process import InProcessLink

        return InProcessLink(config, options.interface, key)
    if options.realtime:
        from .real_time import RealTimeLink

        return RealTimeLink(options, config, cycle_s, key)
    from .lock_step import LockStepLink

    return LockStepLink(options, config, key)
