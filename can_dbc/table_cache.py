"""A cache of what :mod:`can_dbc.database` reads from the DBC, so a process starts without cantools.

Parsing the DBC with cantools costs about 30 ms, and importing cantools 20 to
80 ms more, in every process that encodes or checks a frame: each spawned
``crd ecu`` among them. The facts the codec needs (IDs, cycle times, signal
positions, scaling, limits, ``VAL_`` tables, the SecOC attribute) are a few
kilobytes of plain data, so they are kept as JSON and read back in well under
a millisecond: beside the package, in ``can_dbc/__pycache__/dbc_tables.json``
(where Python keeps its own caches of the package; not in git), or, where that
cannot be written (an installed, read-only package), in the user's cache
directory (``$XDG_CACHE_HOME/crd`` or ``~/.cache/crd``, made mode 0700), named
by the key. The file is written mode 0600.

The cache is never trusted blindly:

* its **key** is the SHA-256 of the DBC's bytes, the source of
  :mod:`can_dbc.database` (which derives the tables) and the cantools version
  (which parses the DBC): a changed DBC, a changed derivation or another
  cantools makes it stale;
* its **digest** is the SHA-256 of the stored tables: a truncated or altered
  file is corrupt;

either way (or unreadable, not JSON, of another shape) it is rebuilt from the
DBC and rewritten atomically (a temporary file renamed over it, so concurrent
starters never read half a file). JSON, not pickle: the file holds data only,
so even a forged one cannot run code. When the directory cannot be written
(a read-only home) the tables are parsed every time, as without a cache.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import tempfile
from pathlib import Path
from typing import Any

log = logging.getLogger(__name__)

#: file name of the cache
CACHE_NAME = "dbc_tables.json"


def cache_paths(package_dir: Path, key: str) -> tuple[Path, Path]:
    """Where the cache may live, in order: beside the package, then in the user's cache directory."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return (package_dir / "__pycache__" / CACHE_NAME, Path(base) / "crd" / f"dbc_tables-{key[:16]}.json")


def cache_key(*parts: bytes) -> str:
    """SHA-256 over ``parts`` (each length-prefixed, so no two sequences collide)."""
    digest = hashlib.sha256()
    for part in parts:
        digest.update(len(part).to_bytes(8, "little"))
        digest.update(part)
    return digest.hexdigest()


def read_first(paths: tuple[Path, ...], key: str) -> tuple[Any, Path] | tuple[None, None]:
    """The tables of the first of ``paths`` that holds them current and sound, and that path."""
    for path in paths:
        tables = read(path, key)
        if tables is not None:
            return tables, path
    return None, None


def write_first(paths: tuple[Path, ...], key: str, tables: Any) -> Path | None:
    """Store ``tables`` in the first of ``paths`` that can be written; that path (None: none could)."""
    return next((path for path in paths if write(path, key, tables)), None)


def read(path: Path, key: str) -> Any | None:
    """The stored tables, or None when the file is missing, stale or corrupt."""
    try:
        with open(path, "rb") as f:
            entry = json.loads(f.read())
        payload = entry["tables"]
        if entry["key"] != key:
            log.debug("%s: stale (another DBC, derivation or cantools); rebuilding", path)
            return None
        if entry["digest"] != hashlib.sha256(payload.encode()).hexdigest():
            log.warning("%s: corrupt (its digest does not match); rebuilding it", path)
            return None
        return json.loads(payload)
    except FileNotFoundError:
        return None
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
        log.warning("%s: unreadable (%s); rebuilding it", path, exc)
        return None


def write(path: Path, key: str, tables: Any) -> bool:
    """Store ``tables`` under ``key`` atomically; False (logged) when the directory is not writable."""
    payload = json.dumps(tables, separators=(",", ":"))
    entry = json.dumps({"key": key, "digest": hashlib.sha256(payload.encode()).hexdigest(), "tables": payload})
    try:
        # __pycache__ as Python makes it (its .pyc files live there too); our own directory private
        path.parent.mkdir(mode=0o777 if path.parent.name == "__pycache__" else 0o700, parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=path.name, suffix=".tmp", dir=path.parent)  # mode 0600
        try:
            with os.fdopen(fd, "w") as f:
                f.write(entry)
            os.replace(tmp, path)
        except BaseException:
            os.unlink(tmp)
            raise
    except OSError as exc:
        log.debug("cannot cache the DBC tables at %s: %s", path, exc)
        return False
    return True
