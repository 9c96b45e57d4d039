"""An FMU file prepared once for many plant runs in this process: hashed, its model description read, extracted,
its library loaded by the first plant (:class:`SharedFmu`, :func:`share_fmu`, :func:`fmu_shared`).

:class:`~cosim.world.plant_fmu.FmuPlant` looks its path up here (:data:`SHARED`) before it loads an FMU itself.
"""

from __future__ import annotations

import hashlib
import logging
import shutil
import threading
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException

from ..errors import PlantError

log = logging.getLogger(__name__)


def file_sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 16), b""):
            digest.update(block)
    return digest.hexdigest()


def read_md(path: Path):
    """The FMU's model description; a broken archive is one :class:`~cosim.errors.PlantError`."""
    try:
        return read_model_description(str(path))
    except Exception as exc:  # noqa: BLE001 - any broken archive becomes one typed error
        raise PlantError(f"{path}: not a readable FMU: {exc}") from exc


class SharedFmu:
    """One FMU file prepared once for many runs in this process (a sweep worker): hashed, its model
    description read, extracted, and (at the first plant) its shared library loaded.

    A :class:`~cosim.world.plant_fmu.FmuPlant` opened on the path of a shared FMU (:func:`share_fmu`) skips all that and
    reuses the loaded library (fmpy's ``FMU2Slave``/``FMU3Slave`` object): it instantiates its own
    instance and, when closed, terminates and frees only that instance (``fmi2FreeInstance`` /
    ``fmi3FreeInstance``), leaving the library loaded. FMI allows instances to come and go in one
    loaded library; a run's results are bit-identical to a fresh load (``tests/cosim/test_sweep_reuse.py``).
    One plant uses it at a time; a second one opened meanwhile loads its own copy as usual.
    """

    def __init__(self, path: Path) -> None:
        self.path = Path(path)
        self.sha256, self.md = file_sha256(self.path), read_md(self.path)
        self.unzipdir = extract(str(self.path))
        self.slave = None  # fmpy FMU2Slave/FMU3Slave, made by the first plant
        self.retired = False  # unshared while busy: closed by the plant using it
        self._lock = threading.Lock()  # held by the plant using it (a worker may run several threads)

    @property
    def busy(self) -> bool:
        return self._lock.locked()

    def claim(self) -> bool:
        """Take it for one plant; False when another plant has it."""
        return self._lock.acquire(blocking=False)

    def unclaim(self) -> None:
        self._lock.release()
        if self.retired:
            self.close()

    def release(self, fmu) -> None:
        """Terminate and free one plant's instance; the library stays loaded."""
        if fmu.component is None:
            return
        try:
            fmu.terminate()
        except FMICallException as exc:
            log.warning("plant FMU terminate failed: %s", exc)
        try:
            getattr(fmu, f"fmi{self.md.fmiVersion[0]}FreeInstance")(fmu.component)
        except Exception as exc:  # noqa: BLE001 - best effort after a failure
            log.warning("plant FMU freeInstance failed: %s", exc)
        fmu.component = None

    def close(self) -> None:
        """Unload the library and delete the extraction (no plant may be using it)."""
        slave, self.slave = self.slave, None
        if slave is not None:
            slave.freeLibrary()
        shutil.rmtree(self.unzipdir, ignore_errors=True)


SHARED: dict[Path, SharedFmu] = {}  # path -> prepared FMU, in this process


def share_fmu(path: Path) -> SharedFmu:
    """Prepare the FMU at ``path`` once for every later :class:`~cosim.world.plant_fmu.FmuPlant` on that path in this process."""
    path = Path(path)
    shared = SHARED.get(path)
    if shared is None:
        shared = SHARED[path] = SharedFmu(path)
    return shared


@contextmanager
def fmu_shared(path: Path) -> Iterator[SharedFmu]:
    """:func:`share_fmu` for the block, unshared after (unless it was shared before): e.g. prepared once
    in a parent before it forks run workers, which then neither parse nor extract it again."""
    owned = Path(path) not in SHARED
    shared = share_fmu(path)
    try:
        yield shared
    finally:
        if owned:
            unshare_fmu(path)


def unshare_fmu(path: Path) -> None:
    """Forget (and unload) the shared FMU at ``path``; plants opened later load it per run again."""
    shared = SHARED.pop(Path(path), None)
    if shared is not None:
        shared.retired = True
        if not shared.busy:  # else the plant using it closes it when it closes
            shared.close()
