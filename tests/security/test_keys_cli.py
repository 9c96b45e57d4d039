"""Key files (mode 0600, 32 hex digits) and ``--key-file`` on crd run / dbc decode / ecu; exit 4 on auth faults."""

import os

import pytest

from can_dbc import KeyFileError, generate_key, load_key_file, write_key_file
from cosim.results.events import EXIT_FAULT_EVENT, fault_exit
from cosim.cli.main import main as crd
from cosim.results.run_record import RunEvent, RunMetrics, RunRecord

SCENARIO = """
[scenario]
name = "short"
duration_s = 1.0
[object]
position_m = 30.0
[radar]
latency_s = 0.0
"""


def test_key_file_round_trip_and_mode(tmp_path):
    key = generate_key()
    path = write_key_file(tmp_path / "k.key", key)
    assert os.stat(path).st_mode & 0o777 == 0o600 and load_key_file(path) == key
    os.chmod(path, 0o640)
    with pytest.raises(KeyFileError, match=r"k.key: expected mode 0600"):
        load_key_file(path)
    bad = tmp_path / "bad.key"
    bad.write_text("abc\n")
    os.chmod(bad, 0o600)
    with pytest.raises(KeyFileError, match=r"bad.key: expected 32 hexadecimal digits"):
        load_key_file(bad)
    with pytest.raises(FileExistsError):
        write_key_file(path, key)  # never overwrites


def test_run_with_a_key_file_and_decode_the_log_with_it(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text(SCENARIO)
    key = write_key_file(tmp_path / "run.key", generate_key())
    assert crd(["run", str(scen), "--out", str(tmp_path / "o"), "--key-file", str(key)]) == 0
    capsys.readouterr()
    assert crd(["dbc", "decode", str(tmp_path / "o" / "tightening" / "can.blf"), "--key-file", str(key)]) == 0
    out = capsys.readouterr().out
    assert "REJECTED" not in out and "rejected: {}" in out
    assert "SafetyOverride {" in out and "WheelSpeeds {" in out


def test_a_key_file_readable_by_others_is_a_one_line_error(tmp_path, capsys):
    scen = tmp_path / "s.toml"
    scen.write_text(SCENARIO)
    key = write_key_file(tmp_path / "run.key", generate_key())
    os.chmod(key, 0o644)
    assert crd(["run", str(scen), "--out", str(tmp_path / "o"), "--key-file", str(key)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("error: ") and "run.key: expected mode 0600" in err[-1]
    assert crd(["ecu", "--interface", "virtual", "--channel", "k", "--key-file", str(key)]) == 1
    assert "run.key: expected mode 0600" in capsys.readouterr().err


def test_security_events_make_the_exit_status_4():
    record = RunRecord("none", RunMetrics("none"))
    assert fault_exit([record]) == 0
    record.events.append(RunEvent(1.0, "auth_failure", "forged"))
    assert fault_exit([record]) == EXIT_FAULT_EVENT == 4
    record.events.append(RunEvent(1.1, "ecu_security_fault", "ECU reports FaultAuth"))
    assert fault_exit([record], expected=["auth_failure"]) == 4
    assert fault_exit([record], expected=["auth_failure", "ecu_security_fault"]) == 0


def test_runs_authenticate_by_default(tmp_path):
    """No key file: a fresh key per run, so every input and SafetyOverride has its authenticator in the log."""
    import can

    from can_dbc import AUTHENTICATORS

    scen = tmp_path / "s.toml"
    scen.write_text(SCENARIO)
    assert crd(["run", str(scen), "--out", str(tmp_path / "o")]) == 0
    ids = [m.arbitration_id for m in can.LogReader(str(tmp_path / "o" / "tightening" / "can.blf"))]
    for name in ("SafetyOverride", "WheelSpeeds", "DriverInput", "ObjectTrack"):
        assert ids.count(AUTHENTICATORS[name]) == ids.count(AUTHENTICATORS[name] - 1) > 0
