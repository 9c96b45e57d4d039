"""What the two links to an ECU on a bus share (:mod:`cosim.link.lock_step`, :mod:`cosim.link.real_time`).

The bus endpoint (a spawned ``crd ecu`` or an attached one), its events, and the check of
the ECU's announcement (:mod:`cosim.link.ecu_identity`): a link joins the ECU, then
believes only the settings it announced.
"""

from __future__ import annotations

from ecu import EcuConfig

from .bus_endpoint import BusEndpoint
from .ecu_identity import IdentityCheck
from .ecu_link import EcuOptions


class BusLink:
    """The endpoint and the identity check of a link over a bus; ``realtime`` is the subclass's pacing."""

    realtime: bool

    def __init__(self, options: EcuOptions, config: EcuConfig, key: bytes | None) -> None:
        self.options = options
        self.endpoint = BusEndpoint(options, config, key)
        self.events = self.endpoint.events
        self._identity = IdentityCheck(config, options.ecu_settings, key)
        self._ecu_settings: dict | None = None

    # what tests and the CLI look at: the spawned process, the bus, whether the ECU was lost
    pid = property(lambda self: self.endpoint.pid)
    process = property(lambda self: self.endpoint.process)
    bus = property(lambda self: self.endpoint.bus)
    lost = property(lambda self: self.endpoint.lost)

    def _join(self, first_frame_joins: bool) -> None:
        """Wait for the ECU (and its announcement, with settings that fit the run)."""
        self.endpoint.join(first_frame_joins=first_frame_joins, seen=self._identity.offer)
        self._ecu_settings = self.endpoint.check_ecu(self._identity, realtime=self.realtime)

    def close(self) -> None:
        self.endpoint.close()
