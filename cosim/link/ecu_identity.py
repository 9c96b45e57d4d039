"""What the ECU on the bus runs, checked before a run starts (issue 25): attach mode that tells the truth.

A standalone ECU (``crd ecu``) announces itself in ``EcuIdentity``: its software
version, strategy, the leading 32 bits of the SHA-256 digest of its settings
(:mod:`ecu.config_digest`) and whether it waits for a run (``RunActive`` 0: a
fresh node, clean state). With a key the frame is SecOC-authenticated.

Before cycle 0, the link waits (bounded) for the announcement of a waiting ECU
(:meth:`IdentityCheck.wait`) and compares it with the run's ``[ecu]``
(``EcuOptions.ecu_settings``, ``crd run --ecu-settings``):

* ``scenario`` (default): the ECU must run the scenario's ``[ecu]`` with the
  strategy of the run and this software version; otherwise the run stops before
  it starts with :class:`EcuSettingsError`, one line naming both digests and how
  to fix it. An ECU that announces nothing is refused the same way;
* ``ecu``: run with whatever the ECU runs; the record says what that was: the
  announced version, strategy and digest, and the settings themselves when the
  digest is that of a configuration known here (the scenario's ``[ecu]``, or
  ``crd ecu``'s defaults for a strategy);
* a path: as ``ecu``, and the ECU's settings are that file (read as ``crd ecu
  --config`` reads it); its digest must be the announced one.

:meth:`IdentityCheck.record` is what the run's ``metrics.json`` and
``report.md`` then show (``ecu_settings``).
"""

from __future__ import annotations

import logging
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

import can

from can_dbc import AUTHENTICATORS, LAYOUTS, FrameError, SecOcVerifier, check_alone, enumeration
from ecu import EcuConfig
from ecu.config_digest import SOFTWARE_VERSION, announced_digest, settings_of, version_text
from ecu.equipment import EQUIPMENT
from ecu.errors import ConfigError

from ..errors import CosimError

log = logging.getLogger(__name__)

IDENTITY_ID = LAYOUTS["EcuIdentity"].frame_id
IDENTITY_AUTH_ID = AUTHENTICATORS["EcuIdentity"]
_STRATEGY_NAMES = {code: name.lower() for code, name in enumeration("EcuIdentity", "ConfigStrategy").items()}
#: ``--ecu-settings`` words (anything else is the path of the ECU's settings file)
SETTINGS_WORDS = ("scenario", "ecu")


class EcuSettingsError(CosimError, ValueError):
    """The ECU on the bus runs other settings than the run was asked to use (or does not say what it runs)."""


@dataclass(frozen=True, slots=True)
class Announcement:
    """One ``EcuIdentity``: what the ECU says it runs."""

    version: tuple[int, int, int]
    strategy: str
    digest: int
    waiting: bool

    @classmethod
    def of(cls, signals) -> "Announcement":
        return cls((int(signals["SoftwareVersionMajor"]), int(signals["SoftwareVersionMinor"]),
                    int(signals["SoftwareVersionPatch"])), _STRATEGY_NAMES[int(signals["ConfigStrategy"])],
                   int(signals["ConfigDigest"]), not signals["RunActive"])

    def describe(self) -> str:
        return f"config digest 0x{self.digest:08x} (strategy {self.strategy}, crd {version_text(self.version)})"


class IdentityCheck:
    """Collects the ECU's announcements and judges them against the run's settings (module docstring)."""

    def __init__(self, config: EcuConfig, settings: str = "scenario", key: bytes | None = None) -> None:
        self._config, self._settings, self._key = config, settings, key
        self._held: can.Message | None = None  # keyed: the EcuIdentity waiting for its authenticator
        self.announcement: Announcement | None = None  # the latest from an ECU that waits for a run
        self.rejected = 0

    def offer(self, msg: can.Message) -> None:
        """Take a frame from the bus (others than ``EcuIdentity`` and its authenticator are ignored)."""
        fid = msg.arbitration_id
        if msg.is_extended_id or fid not in (IDENTITY_ID, IDENTITY_AUTH_ID):
            return
        if self._key is not None:
            if fid == IDENTITY_ID:
                self._held = msg
                return
            held, self._held = self._held, None
            if held is None or not self._verified(held, msg):
                self.rejected += 1
                return
            msg = held
        elif fid != IDENTITY_ID:
            return
        try:
            announcement = Announcement.of(check_alone(msg).signals)
        except FrameError:
            self.rejected += 1
            return
        if announcement.waiting:
            self.announcement = announcement

    def _verified(self, held: can.Message, auth: can.Message) -> bool:
        """The announcement's authenticator verifies. Each ECU node counts its freshness from 0, so each is
        checked on its own (a verifier of its own): a replayed announcement passes, and can at most make an
        ECU look like one that runs other settings."""
        try:
            SecOcVerifier(self._key).verify(IDENTITY_ID, bytes(held.data), bytes(auth.data))
        except FrameError:
            return False
        return True

    def wait(self, recv: Callable[[float], can.Message | None], timeout_s: float, who: str) -> dict:
        """Frames from ``recv`` until an ECU waiting for a run has announced itself (at most ``timeout_s``);
        then :meth:`record` (an :class:`EcuSettingsError` if it does not fit)."""
        deadline = time.monotonic() + (timeout_s if self._settings == "scenario" else min(timeout_s, 2.5))
        while self.announcement is None and (remaining := deadline - time.monotonic()) > 0.0:
            msg = recv(remaining)
            if msg is not None:
                self.offer(msg)
        return self.record(who)

    def record(self, who: str) -> dict:
        """What the run records of the ECU's settings; raises :class:`EcuSettingsError` where they do not fit."""
        expected = announced_digest(self._config)
        seen = self.announcement
        entry = {"source": self._settings, "announced": seen is not None,
                 "scenario_config_digest": f"0x{expected:08x}", "software_version": None, "strategy": None,
                 "config_digest": None, "known_as": None, "settings": None}
        if seen is None:
            if self._settings == "scenario":
                raise EcuSettingsError(f"{who} did not announce what it runs (no EcuIdentity of an ECU "
                                       "waiting for a run): its settings cannot be checked against the scenario's "
                                       "[ecu]; pass --ecu-settings ecu to run with them unchecked")
            return entry
        entry.update(software_version=version_text(seen.version), strategy=seen.strategy,
                     config_digest=f"0x{seen.digest:08x}")
        known = self._known(seen)
        if self._settings == "scenario" and (seen.digest != expected or seen.version != SOFTWARE_VERSION):
            hint = f"; its digest is that of {known[0]}" if known else ""
            raise EcuSettingsError(
                f"{who} runs other settings than the scenario's [ecu]: it announces {seen.describe()}, "
                f"the scenario's [ecu] gives config digest 0x{expected:08x} (strategy {self._config.strategy}, crd "
                f"{version_text(SOFTWARE_VERSION)}){hint}; start it with crd ecu --config SCENARIO, or pass "
                "--ecu-settings ecu to run with the ECU's own settings")
        if known is not None:
            entry["known_as"], entry["settings"] = known[0], settings_of(known[1])
        return entry

    def _known(self, seen: Announcement) -> tuple[str, EcuConfig] | None:
        """A configuration known here whose digest is the announced one (the named settings file must be)."""
        if self._settings not in SETTINGS_WORDS:
            path = Path(self._settings)
            try:
                named = EcuConfig.from_toml(path)
            except ConfigError as exc:
                raise EcuSettingsError(f"--ecu-settings {path}: {exc}") from None
            if announced_digest(named) != seen.digest:
                raise EcuSettingsError(f"--ecu-settings {path}: its settings give config digest "
                                       f"0x{announced_digest(named):08x}, the ECU announces {seen.describe()}")
            return f"the settings file {path}", named
        candidates = [("the scenario's [ecu]", self._config)]
        candidates += [(f"crd ecu's defaults for strategy {name}", EcuConfig(strategy=name))
                       for name in _STRATEGY_NAMES.values()]
        # the scenario's [ecu] read without the scene (crd ecu --config SCENARIO), which gives the equipment
        candidates += [(f"the scenario's [ecu] with equipment {name!r} instead of this scene's "
                        f"{self._config.equipment!r} (state equipment = {self._config.equipment!r} in the [ecu] "
                        "crd ecu reads)", replace(self._config, equipment=name))
                       for name in EQUIPMENT if name != self._config.equipment]
        return next(((name, cfg) for name, cfg in candidates if announced_digest(cfg) == seen.digest), None)
