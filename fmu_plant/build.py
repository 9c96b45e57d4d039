"""Build the vehicle plant FMU (FMI 2.0 or 3.0 co-simulation) from source with cmake and gcc.

The build first stages the FMU's ``sources/`` folder (the C files of that FMI version,
the headers, the generated ``plant_token.h`` and, for FMI 3, ``buildDescription.xml``),
compiles the shipped binary from exactly that folder, and zips both: an importer can
rebuild the binary from the FMU alone (e.g. ``fmpy.build.build_platform_binary``).

``build_fmu(fmi_version, out)`` always builds. ``ensure_fmu(fmi_version)`` returns a
cached FMU, building it on first use; the cache entry is keyed by the SHA-256 of
every source file, the FMI headers and the FMI version, so any edit rebuilds.
Concurrent builders are safe: each builds in its own temporary directory inside
the cache and publishes it with an atomic ``os.rename``; a loser discards its copy.

Exceptions::

    FmuBuildError (RuntimeError)
     +-- ToolchainMissingError (also FileNotFoundError): cmake, gcc or FMI headers absent
     +-- CompileError: cmake configure or build failed (message holds the output tail)
"""

from __future__ import annotations

import hashlib
import logging
import os
import shutil
import subprocess
import tempfile
import zipfile
from pathlib import Path

from fmu_plant.description import (MODEL_IDENTIFIER, SOURCE_FILES, SOURCE_HEADERS, render,
                                   render_build_description, render_token_header)

log = logging.getLogger(__name__)

PACKAGE_DIR = Path(__file__).resolve().parent
DEFAULT_CACHE_DIR = PACKAGE_DIR / "_build"
FMU_NAME = f"{MODEL_IDENTIFIER}.fmu"
#: files (relative to the package) whose content defines the FMU
SOURCE_GLOBS = ("CMakeLists.txt", "src/*", "variables.py", "description.py", "build.py")
#: platform folder inside the FMU's binaries/ for each FMI version (Linux only)
_OUTPUT_TAIL_CHARS = 4000
_ZIP_TIME = (1980, 1, 1, 0, 0, 0)


class FmuBuildError(RuntimeError):
    """The FMU could not be built."""


class ToolchainMissingError(FmuBuildError, FileNotFoundError):
    """cmake, gcc or the FMI API headers are not available."""


class CompileError(FmuBuildError):
    """cmake configure or build failed; the message ends with the compiler output tail."""


def _check_version(fmi_version: int) -> int:
    if fmi_version not in (2, 3):
        raise ValueError(f"fmi_version must be 2 or 3, got {fmi_version!r}")
    return fmi_version


def fmi_headers_dir() -> Path:
    """The standard FMI 2/3 API headers shipped with fmpy (``fmpy/c-code``)."""
    import fmpy  # deferred: only a build needs it

    headers = Path(fmpy.__file__).resolve().parent / "c-code"
    for name in ("fmi2Functions.h", "fmi3Functions.h"):
        if not (headers / name).is_file():
            raise ToolchainMissingError(f"FMI header {name} expected in {headers}, not found")
    return headers


def _source_files() -> list[Path]:
    files = {p for pattern in SOURCE_GLOBS for p in PACKAGE_DIR.glob(pattern) if p.is_file()}
    return sorted(files)


def source_hash(fmi_version: int) -> str:
    """SHA-256 over the FMI version, the sources and the FMI headers (hex)."""
    digest = hashlib.sha256(f"fmi{_check_version(fmi_version)}\n".encode())
    headers = fmi_headers_dir()
    named = [(p.relative_to(PACKAGE_DIR).as_posix(), p) for p in _source_files()]
    named += [(f"headers/{p.name}", p) for p in sorted(headers.glob(f"fmi{fmi_version}*.h"))]
    for name, path in named:
        digest.update(name.encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def instantiation_token(fmi_version: int) -> str:
    """GUID-shaped token derived from the source hash, e.g. ``{1a2b3c4d-...}``."""
    h = source_hash(fmi_version)
    return f"{{{h[0:8]}-{h[8:12]}-{h[12:16]}-{h[16:20]}-{h[20:32]}}}"


def _platform_dir(fmi_version: int) -> str:
    import fmpy

    return fmpy.platform if fmi_version == 2 else fmpy.platform_tuple


def _tool(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        raise ToolchainMissingError(f"{name} is required to build the plant FMU; not found on PATH")
    return path


def _run(cmd: list[str], what: str) -> None:
    log.debug("%s: %s", what, " ".join(cmd))
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, check=False)
    if proc.returncode != 0:
        tail = proc.stdout[-_OUTPUT_TAIL_CHARS:]
        raise CompileError(f"{what} failed with exit code {proc.returncode} (expected 0):\n{tail}")


def source_members(fmi_version: int, token: str) -> dict[str, bytes]:
    """The FMU's ``sources/`` folder: file name -> content."""
    src = PACKAGE_DIR / "src"
    members = {name: (src / name).read_bytes() for name in (*SOURCE_FILES[fmi_version], *SOURCE_HEADERS[fmi_version])}
    members["plant_token.h"] = render_token_header(token).encode()
    if fmi_version == 3:
        members["buildDescription.xml"] = render_build_description().encode()
    return members


def _stage_sources(members: dict[str, bytes], sources_dir: Path) -> None:
    sources_dir.mkdir(parents=True)
    for name, data in members.items():
        (sources_dir / name).write_bytes(data)


def _compile(sources_dir: Path, build_dir: Path) -> Path:
    cmake, gcc = _tool("cmake"), _tool("gcc")
    _run([cmake, "-S", str(PACKAGE_DIR), "-B", str(build_dir), f"-DCMAKE_C_COMPILER={gcc}",
          "-DCMAKE_BUILD_TYPE=Release", f"-DPLANT_SOURCES_DIR={sources_dir}",
          f"-DFMI_HEADERS_DIR={fmi_headers_dir()}"], "cmake configure")
    _run([cmake, "--build", str(build_dir)], "cmake build")
    library = build_dir / f"{MODEL_IDENTIFIER}.so"
    if not library.is_file():
        raise CompileError(f"cmake build succeeded but {library} was not produced")
    return library


def _zip_fmu(fmi_version: int, token: str, library: Path, sources: dict[str, bytes], out: Path) -> None:
    members = {
        "modelDescription.xml": render(fmi_version, token).encode(),
        f"binaries/{_platform_dir(fmi_version)}/{MODEL_IDENTIFIER}.so": library.read_bytes(),
        **{f"sources/{name}": data for name, data in sorted(sources.items())},
    }
    with zipfile.ZipFile(out, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name, data in members.items():
            info = zipfile.ZipInfo(name, date_time=_ZIP_TIME)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            zf.writestr(info, data)


def build_fmu(fmi_version: int, out: Path | str) -> Path:
    """Compile the plant and write the FMU to ``out`` (replaced atomically). Returns ``out``."""
    _check_version(fmi_version)
    out = Path(out).resolve()
    out.parent.mkdir(parents=True, exist_ok=True)
    token = instantiation_token(fmi_version)
    with tempfile.TemporaryDirectory(prefix=".fmu-build-", dir=out.parent) as tmp:
        sources = source_members(fmi_version, token)
        _stage_sources(sources, Path(tmp) / "sources")
        library = _compile(Path(tmp) / "sources", Path(tmp) / "cmake")
        staged = Path(tmp) / FMU_NAME
        _zip_fmu(fmi_version, token, library, sources, staged)
        os.replace(staged, out)
    log.info("built FMI %d plant FMU %s", fmi_version, out)
    return out


def ensure_fmu(fmi_version: int = 2, cache_dir: Path | str | None = None) -> Path:
    """Path of the cached FMU for ``fmi_version``, building it first if it is not cached."""
    _check_version(fmi_version)
    cache = Path(cache_dir) if cache_dir is not None else DEFAULT_CACHE_DIR
    entry = cache.resolve() / f"fmi{fmi_version}-{source_hash(fmi_version)[:20]}"
    fmu = entry / FMU_NAME
    if fmu.is_file():
        return fmu
    cache.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".staging-", dir=cache))
    try:
        build_fmu(fmi_version, staging / FMU_NAME)
        try:
            os.rename(staging, entry)  # atomic publish; fails if another process won
        except OSError:
            if not fmu.is_file():
                raise
            log.debug("another process published %s first", entry)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return fmu
