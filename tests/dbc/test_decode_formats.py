"""``crd dbc decode`` reads every log format its help names, and the help names what python-can reads."""

from __future__ import annotations

import can
import pytest

from can_dbc import encode
from can_dbc.cli import LOG_SUFFIXES
from cosim.cli.main import main

def write_log(path, frames, period_s: float = 0.01) -> None:
    """``frames`` to the log at ``path`` (python-can picks the writer by suffix), stamped 1 s + k * period."""
    with can.Logger(str(path)) as logger:
        for k, msg in enumerate(frames):
            msg.timestamp = 1.0 + period_s * k
            logger.on_message_received(msg)


WRITABLE = (".asc", ".blf", ".csv", ".log", ".trc")  # the text and binary formats python-can writes without extras


def test_help_lists_python_cans_readers(capsys):
    with pytest.raises(SystemExit):
        main(["dbc", "--help"])
    help_text = capsys.readouterr().out
    assert {".blf", ".asc", ".trc", ".log", ".csv"} <= set(LOG_SUFFIXES)
    for suffix in LOG_SUFFIXES:
        assert suffix in help_text, suffix


@pytest.mark.parametrize("suffix", WRITABLE)
def test_each_format_decodes(tmp_path, capsys, suffix):
    path = tmp_path / f"log{suffix}"
    frames = [encode("DriverInput", {"AccelPedal": 42.0, "BrakePedal": 0.0,
                                     "SteeringWheelAngle": 0.0, "SteeringWheelRate": 0.0}, counter=k)
              for k in range(3)]
    write_log(path, frames)
    assert main(["dbc", "decode", str(path)]) == 0
    out = capsys.readouterr().out
    assert out.count("DriverInput {") == 3, out
    assert "'AccelPedal': 42.0" in out
    assert "3 frames" in out
