"""A run's CAN log replays with python-can's player (``python -m can.player``)."""

import subprocess
import sys

import can

from cosim.cli.main import main as crd


def test_blf_replays_with_can_player(tmp_path):
    scen = tmp_path / "s.toml"
    scen.write_text('[scenario]\nduration_s = 0.5\n[object]\nposition_m = 30.0\n[ecu]\nstrategy = "none"\n')
    assert crd(["run", str(scen), "--out", str(tmp_path / "o")]) == 0
    log = tmp_path / "o" / "none" / "can.blf"
    frames = list(can.LogReader(str(log)))
    assert len(frames) > 100
    out = subprocess.run(
        [sys.executable, "-m", "can.player", "-i", "virtual", "-c", "replay", "--ignore-timestamps", "-v",
         str(log)],
        capture_output=True, text=True, timeout=120, check=True)
    replayed = [line for line in out.stdout.splitlines() if "ID:" in line]
    assert len(replayed) == len(frames)
    assert any(" 0c0 " in line.lower() for line in replayed)
