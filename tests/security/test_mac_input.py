"""The SecOC MAC is CMAC-AES-128 over data ID (2 bytes) | frame | freshness value (8 bytes), big-endian.

Computed here independently with ``cryptography`` and compared with the sender's authenticator and
the verifier, for the 8-byte frames of the contract (packed in one ``struct`` call) and for a frame
of another length (joined from its pieces).
"""

from __future__ import annotations

import pytest
from cryptography.hazmat.primitives.ciphers import algorithms
from cryptography.hazmat.primitives.cmac import CMAC

from can_dbc import AUTHENTICATORS, LAYOUTS, AuthError, SecOcSender, SecOcVerifier, encode

KEY = bytes(range(16))


def _reference_mac(data_id: int, frame: bytes, fv: int) -> bytes:
    cmac = CMAC(algorithms.AES(KEY))
    cmac.update(data_id.to_bytes(2, "big") + bytes(frame) + fv.to_bytes(8, "big"))
    return cmac.finalize()[:6]


@pytest.mark.parametrize("frame", [bytes(range(8)), bytes(range(7)), bytes(range(12))])
@pytest.mark.parametrize("fv", [0, 1, 65_536 + 5])
def test_mac_is_cmac_over_id_frame_and_freshness(frame, fv):
    data_id = LAYOUTS["WheelSpeeds"].frame_id
    assert SecOcSender(KEY).mac(data_id, frame, fv) == _reference_mac(data_id, frame, fv)


def test_authenticator_carries_the_reference_mac_and_verifies():
    sender, verifier = SecOcSender(KEY), SecOcVerifier(KEY)
    data_id = LAYOUTS["SafetyOverride"].frame_id
    for fv in range(3):
        msg = encode("SafetyOverride", {"Mode": 1, "OverrideActive": 1, "ThrottleLimit": 20.0,
                                        "BrakeDecelRequest": 1.0}, fv)
        auth = sender.authenticator(msg)
        assert auth.arbitration_id == AUTHENTICATORS["SafetyOverride"]
        assert bytes(auth.data) == fv.to_bytes(2, "little") + _reference_mac(data_id, msg.data, fv)
        assert verifier.verify(data_id, msg.data, auth.data) == fv
    forged = bytearray(auth.data)
    forged[7] ^= 1
    with pytest.raises(AuthError):
        verifier.verify(data_id, msg.data, forged)
