"""What an ECU runs, in a few bytes: its software version and a digest of its settings (issue 25).

An ECU attached to the co-simulation (``crd ecu`` + ``crd run --ecu attach``) announces
both in its ``EcuIdentity`` frame (:func:`identity_signals`), so that the run can
check them against the scenario's ``[ecu]`` and record what the ECU really used. Both
sides compute the digest from an :class:`~ecu.config.EcuConfig`, with the same pure
function:

    settings = {name: value for every init field of EcuConfig except NOT_DIGESTED}
    canonical = JSON of [DIGEST_SCHEME, [[name, value] ... in name order]]
                (floats as Python's shortest round-trip repr, ints as ints, no spaces)
    config_digest = SHA-256(canonical)           (FIPS 180-4)
    announced     = its leading 32 bits, big-endian (EcuIdentity.ConfigDigest)

Values are normalised to their field's type first (a TOML integer where a float is
declared is that float), so equal configurations give equal digests however they were
written. Left out (``NOT_DIGESTED``): ``sim_time`` (how the ECU is paced, which the run
sees from the link; the co-simulation spawns a sim-time ECU from a config without it) and
``key_file`` (where the key lies: the same key may lie in two places; whether the ECU
authenticates shows on the bus). 32 bits tell two configurations apart by accident with
probability 2**-32; they are a check against mistakes, not against an attacker (against
one, the frame is SecOC-authenticated when a key is configured).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import fields
from typing import Any, Mapping

from .config import EcuConfig

#: the ECU's software version, announced with its settings (tests/ecu/test_config_digest.py keeps it
#: equal to the package's); read here rather than from the installed metadata at every start (10 ms)
SOFTWARE_VERSION = (0, 1, 0)
#: the version of the digest's definition above (a change of it changes every digest)
DIGEST_SCHEME = 1
#: EcuConfig fields the digest leaves out (see the module docstring)
NOT_DIGESTED = frozenset({"sim_time", "key_file"})


def settings_of(config: EcuConfig) -> dict[str, Any]:
    """The settings that make up the digest: every init field but ``NOT_DIGESTED``, typed as declared."""
    out = {}
    for f in fields(config):
        if not f.init or f.name in NOT_DIGESTED:
            continue
        value = getattr(config, f.name)
        kind = type(f.default)
        out[f.name] = value if kind is bool or kind is str else kind(value)
    return out


def digest_of(settings: Mapping[str, Any]) -> bytes:
    """SHA-256 of the canonical form of ``settings`` (a mapping as :func:`settings_of` gives)."""
    canonical = json.dumps([DIGEST_SCHEME, sorted([name, value] for name, value in settings.items())],
                           separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(canonical.encode()).digest()


def config_digest(config: EcuConfig) -> bytes:
    """The SHA-256 digest of ``config``'s settings (module docstring)."""
    return digest_of(settings_of(config))


def announced_digest(config: EcuConfig) -> int:
    """The leading 32 bits of :func:`config_digest`, as ``EcuIdentity.ConfigDigest`` carries them."""
    return int.from_bytes(config_digest(config)[:4], "big")


def version_text(version: tuple[int, int, int]) -> str:
    return ".".join(str(part) for part in version)


def identity_signals(config: EcuConfig) -> dict[str, int]:
    """The ``EcuIdentity`` signals of an ECU running ``config`` (but ``RunActive``: the node knows it)."""
    major, minor, patch = SOFTWARE_VERSION
    return {"ConfigStrategy": config.strategy_code, "SoftwareVersionMajor": major, "SoftwareVersionMinor": minor,
            "SoftwareVersionPatch": patch, "ConfigDigest": announced_digest(config)}
