"""CAN logs as measurement files (issue 13, finding 3): several per run, MF4 through asammdf,
a deterministic absolute start time in every header, and bad options refused before the run.

One short run writes every format; the tests read them back with the tools engineers use:
asammdf (``extract_bus_logging`` with our DBC), python-can's readers and cantools.
"""

import subprocess
import sys
from datetime import datetime, timezone

import can
import cantools
import pytest

from can_dbc import DBC_PATH
from cosim.cli.main import main as crd
from cosim.scenarios.config import DEFAULT_START_TIME

asammdf = pytest.importorskip("asammdf", reason="asammdf is in the test extra (crd[mdf])")

SCENARIO = '[scenario]\nduration_s = 2.0\n{extra}[object]\nposition_m = 30.0\n[ecu]\nstrategy = "none"\n'
LOGS = ("x.asc", "x.mf4", "x.trc")


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("logs")
    (tmp / "s.toml").write_text(SCENARIO.format(extra=""))
    args = ["run", str(tmp / "s.toml"), "--out", str(tmp / "o")]
    for name in LOGS:
        args += ["--can-log", name]
    assert crd(args) == 0
    return tmp / "o" / "none"


def _frames(path):
    return list(can.LogReader(str(path)))


def test_every_log_is_written_besides_can_blf(run_dir):
    for name in ("can.blf",) + LOGS:
        assert (run_dir / name).stat().st_size > 1000, name
    blf, asc, trc = (_frames(run_dir / n) for n in ("can.blf", "x.asc", "x.trc"))
    assert len(blf) == len(asc) == len(trc) > 500
    assert [(m.arbitration_id, bytes(m.data)) for m in blf] == [(m.arbitration_id, bytes(m.data)) for m in asc]


def test_headers_carry_the_start_time_not_1970(run_dir):
    start = datetime.fromisoformat(DEFAULT_START_TIME)
    assert start.year == 2020
    with can.BLFReader(str(run_dir / "can.blf")) as reader:
        assert reader.start_timestamp == start.timestamp()
        first = next(iter(reader))
    assert first.timestamp == pytest.approx(start.timestamp())
    head = (run_dir / "x.asc").read_text().splitlines()[:4]
    assert head[0] == "date Wed Jan 01 00:00:00.0 2020" and head[3].startswith("Begin Triggerblock Wed Jan 01")
    with can.TRCReader(str(run_dir / "x.trc")) as reader:
        list(reader)
        assert reader.start_time == start
    mdf = asammdf.MDF(str(run_dir / "x.mf4"))
    try:
        assert mdf.header.start_time == start
    finally:
        mdf.close()


def test_time_stamps_are_start_plus_sim_time(run_dir):
    start_s = datetime.fromisoformat(DEFAULT_START_TIME).timestamp()
    blf = [m.timestamp - start_s for m in _frames(run_dir / "can.blf")]
    asc = [m.timestamp for m in _frames(run_dir / "x.asc")]  # ASC readers give offsets by default
    assert blf[0] == pytest.approx(0.0, abs=1e-6) and asc[0] == 0.0
    assert blf == pytest.approx(asc, abs=1e-6)
    assert max(asc) == pytest.approx(1.99)  # the last 10 ms cycle of a 2 s run


def test_mf4_decodes_with_asammdf_extract_bus_logging(run_dir):
    """asammdf decodes the MF4 with our DBC; values and times match cantools on the BLF."""
    mdf = asammdf.MDF(str(run_dir / "x.mf4"))
    try:
        decoded = mdf.extract_bus_logging({"CAN": [(str(DBC_PATH), 0)]})
        ranges = decoded.get("ObjectRange")
        pedal = decoded.get("AccelPedal")
    finally:
        mdf.close()
    db = cantools.database.load_file(str(DBC_PATH))
    start_s = datetime.fromisoformat(DEFAULT_START_TIME).timestamp()
    tracks = [m for m in _frames(run_dir / "can.blf") if m.arbitration_id == 0x0C0]
    expected = [db.decode_message(0x0C0, bytes(m.data))["ObjectRange"] for m in tracks]
    assert len(ranges.samples) == len(tracks) == 40  # ObjectTrack every 50 ms for 2 s
    assert list(ranges.samples) == pytest.approx(expected)
    assert ranges.timestamps[0] == 0.0  # the MF4 time axis starts at 0 ...
    assert list(ranges.timestamps) == pytest.approx([m.timestamp - start_s for m in tracks], abs=1e-6)
    assert ranges.samples[0] == pytest.approx(30.0, abs=0.05)
    assert set(pedal.samples) == {100.0}  # the full-throttle driver


def test_scenario_start_time_reaches_every_header(tmp_path):
    (tmp_path / "s.toml").write_text(SCENARIO.format(extra="start_time = 2024-05-01T08:30:00+02:00\n"))
    out = tmp_path / "o"
    assert crd(["run", str(tmp_path / "s.toml"), "--out", str(out), "--can-log", "x.mf4",
                "--can-log", "x.asc"]) == 0
    start = datetime(2024, 5, 1, 6, 30, tzinfo=timezone.utc)
    with can.BLFReader(str(out / "none" / "can.blf")) as reader:
        assert reader.start_timestamp == start.timestamp()
    mdf = asammdf.MDF(str(out / "none" / "x.mf4"))
    try:
        assert mdf.header.start_time == start
    finally:
        mdf.close()
    assert (out / "none" / "x.asc").read_text().startswith("date Wed May 01 08:30:00.0 2024\n")
    assert 'start_time = "2024-05-01T08:30:00+02:00"' in (out / "config.resolved.toml").read_text()


@pytest.mark.parametrize("name, fragment", [
    ("x.foo", "--can-log x.foo: expected a suffix in"),
    ("sub/x.asc", "--can-log: expected a file name"),
])
def test_bad_log_name_fails_before_the_run(tmp_path, capsys, name, fragment):
    (tmp_path / "s.toml").write_text(SCENARIO.format(extra=""))
    assert crd(["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o"), "--can-log", name]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("error: ") and fragment in err[-1]
    assert not (tmp_path / "o").exists()  # nothing ran


def test_mf4_without_asammdf_fails_before_the_run(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "asammdf", None)  # as if the crd[mdf] extra were not installed
    (tmp_path / "s.toml").write_text(SCENARIO.format(extra=""))
    assert crd(["run", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o"), "--can-log", "x.mf4"]) == 1
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "MF4 needs asammdf" in err and "pip install 'crd[mdf]'" in err
    assert not (tmp_path / "o").exists()


def test_crd_command_keeps_asammdf_for_mf4(tmp_path):
    """The ``crd`` command starts without asammdf unless a .mf4 is named (python-can would import it
    eagerly); naming one, in any letter case, still writes it."""
    (tmp_path / "s.toml").write_text(SCENARIO.format(extra=""))
    subprocess.run([sys.executable, "-m", "cosim.cli.main", "run", str(tmp_path / "s.toml"), "--out",
                    str(tmp_path / "o"), "--can-log", "X.MF4"], check=True, capture_output=True, timeout=300)
    mdf = asammdf.MDF(str(tmp_path / "o" / "none" / "X.MF4"))
    try:
        assert len(mdf.get("CAN_DataFrame.ID").samples) > 500
    finally:
        mdf.close()
