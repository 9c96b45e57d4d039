"""What an export (ARXML, KCD, SYM) must keep of our messages: shared by the contract tests."""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

import can
import cantools

from can_dbc import DATABASE
from can_dbc.export import export


def assert_exported(fmt: str, tmp_path: Path, names: Iterable[str], sample: can.Message) -> None:
    """The ``fmt`` export of the DBC, loaded back by cantools, has each of ``names`` with our frame ID and signal
    layout, and decodes ``sample`` as the DBC does."""
    other = cantools.database.load_file(str(export(fmt, tmp_path / f"exported.{fmt}")))
    for name in names:
        ours, theirs = DATABASE.get_message_by_name(name), other.get_message_by_name(name)
        assert theirs.frame_id == ours.frame_id, name
        assert [(s.name, s.start, s.length, s.scale, s.is_signed) for s in theirs.signals] == \
               [(s.name, s.start, s.length, s.scale, s.is_signed) for s in ours.signals], name
    assert other.decode_message(sample.arbitration_id, sample.data) == \
        DATABASE.decode_message(sample.arbitration_id, sample.data)
