"""Issue 25: the EcuIdentity frame in the contract's other forms (ARXML, KCD, SYM) and in ``crd dbc decode``."""

from __future__ import annotations

import can
import cantools
import pytest

from can_dbc import DATABASE, SecOcSender, encode, generate_key, write_key_file
from can_dbc.export import export
from cosim.cli.main import main as crd

SIGNALS = {"ConfigStrategy": 3, "RunActive": 1, "SoftwareVersionMajor": 15, "SoftwareVersionMinor": 42,
           "SoftwareVersionPatch": 63, "ConfigDigest": 0xDEADBEEF}


@pytest.mark.parametrize("fmt", ["arxml", "kcd", "sym"])
def test_the_exports_decode_ecu_identity_as_the_dbc_does(fmt, tmp_path):
    other = cantools.database.load_file(str(export(fmt, tmp_path / f"c.{fmt}")))
    msg = encode("EcuIdentity", SIGNALS, 5)
    ours = DATABASE.decode_message(msg.arbitration_id, msg.data, decode_choices=False)
    assert other.decode_message(msg.arbitration_id, msg.data, decode_choices=False) == ours
    assert ours["ConfigDigest"] == 0xDEADBEEF and ours["SoftwareVersionMinor"] == 42


def test_crd_dbc_decode_verifies_an_announcement_with_the_key(tmp_path, capsys):
    key = generate_key()
    signer = SecOcSender(key)
    frames = []
    for counter in range(3):
        msg = encode("EcuIdentity", SIGNALS, counter)
        frames += [msg, signer.authenticator(msg)]
    forged = encode("EcuIdentity", dict(SIGNALS, ConfigDigest=1), 3)
    frames += [forged, can.Message(arbitration_id=forged.arbitration_id + 1, data=bytes(8), is_extended_id=False)]
    log = tmp_path / "id.blf"
    with can.BLFWriter(str(log)) as writer:
        for i, msg in enumerate(frames):
            msg.timestamp = 1577836800.0 + i * 0.25
            writer.on_message_received(msg)
    assert crd(["dbc", "decode", str(log), "--key-file", str(write_key_file(tmp_path / "k.key", key))]) == 0
    out = capsys.readouterr().out
    assert out.count("EcuIdentity {") == 3 and "'ConfigDigest': 3735928559" in out
    assert "REJECTED AuthError" in out  # the forged announcement
