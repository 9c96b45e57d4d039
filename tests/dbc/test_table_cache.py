"""can_dbc.table_cache: the DBC's tables from a cache that is rebuilt when stale, corrupt or unusable."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from can_dbc import database, table_cache


def _paths(tmp_path: Path) -> tuple[Path, ...]:
    return (tmp_path / "pkg" / "dbc_tables.json", tmp_path / "user" / "dbc_tables-x.json")


def _fresh() -> dict:
    return database._layouts(database._extract(database._parse()))


def _no_parse(monkeypatch) -> None:
    def refuse():
        raise AssertionError("the DBC was parsed although the cache is current")
    monkeypatch.setattr(database, "_parse", refuse)


def test_the_cached_tables_equal_a_fresh_parse_and_spare_it(tmp_path: Path, monkeypatch) -> None:
    paths = _paths(tmp_path)
    messages, layouts = database._load(paths)
    assert paths[0].exists() and layouts == _fresh() == dict(database.LAYOUTS)
    _no_parse(monkeypatch)
    again_messages, again = database._load(paths)
    assert again == layouts and again_messages == messages


@pytest.mark.parametrize("damage", ["truncate", "flip", "garbage", "stale", "shape"])
def test_a_damaged_or_stale_cache_is_rebuilt(tmp_path: Path, damage: str) -> None:
    paths = _paths(tmp_path)
    database._load(paths)
    path = paths[0]
    text = path.read_text()
    entry = json.loads(text)
    if damage == "truncate":
        path.write_text(text[: len(text) // 2])
    elif damage == "flip":  # a changed number in the tables: the digest no longer matches
        path.write_text(text.replace('"frame_id\\":1', '"frame_id\\":9', 1))
        assert path.read_text() != text
    elif damage == "garbage":
        path.write_bytes(b"\x00\xff not json")
    elif damage == "stale":  # another DBC, derivation or cantools
        path.write_text(json.dumps({**entry, "key": "0" * 64}))
    else:  # sound JSON with the right digest, of a shape that is no DBC extract
        tables = json.dumps([{"name": "SafetyOverride"}])
        table_cache.write(path, entry["key"], json.loads(tables))
    _messages, layouts = database._load(paths)
    assert layouts == _fresh()
    assert json.loads(path.read_text())["tables"] == entry["tables"]  # rewritten whole


def test_an_unwritable_package_dir_falls_back_to_the_user_cache(tmp_path: Path) -> None:
    paths = _paths(tmp_path)
    paths[0].parent.write_text("a file where the cache directory would be")  # cannot be written, even by root
    assert not table_cache.write(paths[0], "k", [])
    assert database._load(paths)[1] == _fresh()
    assert paths[1].exists() and paths[1].stat().st_mode & 0o777 == 0o600
    assert paths[1].parent.stat().st_mode & 0o777 == 0o700


def test_a_process_with_a_current_cache_never_imports_cantools() -> None:
    code = "import sys, can_dbc, ecu; print('cantools' in sys.modules)"
    subprocess.run([sys.executable, "-c", "import can_dbc"], check=True)  # makes the cache current
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    assert out.strip() == "False"
