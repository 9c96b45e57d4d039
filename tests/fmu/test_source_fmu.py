"""The FMU carries its sources: fmpy rebuilds the binary from the FMU alone, and the
shipped binary needs no newer glibc than the architecture's first.

The rebuild runs cmake + the C compiler once per FMI version (about 2 s each).
"""

import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.build import build_platform_binary

from tests.fmu.plant_runner import OUTPUTS, run_plant
from tests.fmu.reference_trajectory import STOP_S, load_reference
from tests.fmu.test_integration import dance

#: newest glibc symbol version the shipped binary may need: manylinux2014's baseline
#: (x86_64 itself needs only 2.2.5, aarch64 2.17)
GLIBC_LIMIT = (2, 17)


def rebuilt_fmu(fmu: Path, tmp: Path) -> Path:
    """``fmu`` with its binaries/ removed and rebuilt by fmpy from sources/, zipped again."""
    unzipped = tmp / "unzipped"
    with zipfile.ZipFile(fmu) as zf:
        zf.extractall(unzipped)
    shutil.rmtree(unzipped / "binaries")
    build_platform_binary(unzipped, build_dir=tmp / "build")
    out = tmp / fmu.name
    with zipfile.ZipFile(out, "w") as zf:
        for path in sorted(unzipped.rglob("*")):
            if path.is_file():
                zf.write(path, path.relative_to(unzipped).as_posix())
    return out


@pytest.mark.parametrize("version", [2, 3])
def test_fmpy_rebuilds_the_binary_from_the_fmu_alone(fmus, version, tmp_path):
    if shutil.which("cmake") is None or shutil.which("cc") is None:
        pytest.skip("cmake and a C compiler are needed to rebuild the FMU from its sources")
    md = read_model_description(str(fmus[version]))
    assert md.buildConfigurations, "no SourceFiles (FMI 2) / sources/buildDescription.xml (FMI 3)"
    (tmp_path / "build").mkdir()
    fmu = rebuilt_fmu(fmus[version], tmp_path)
    ref = load_reference()
    run = run_plant(fmu, version, STOP_S, 0.05, dance)
    for name in OUTPUTS:  # the same sources give the same trajectory, bit for bit
        np.testing.assert_array_equal(run[name], ref[name], err_msg=name)


def glibc_versions(library: bytes, tmp: Path) -> dict[str, tuple[int, ...]]:
    """Symbol -> GLIBC version the shared library needs, from ``objdump -T``."""
    path = tmp / "plant.so"
    path.write_bytes(library)
    table = subprocess.run(["objdump", "-T", str(path)], capture_output=True, text=True, check=True).stdout
    found = re.findall(r"\(GLIBC_([0-9.]+)\)\s+(\S+)", table)
    return {symbol: tuple(int(p) for p in version.split(".")) for version, symbol in found}


@pytest.mark.parametrize("version", [2, 3])
def test_the_shipped_binary_needs_no_newer_glibc_than_it_must(fmus, version, tmp_path):
    if shutil.which("objdump") is None:
        pytest.skip("objdump (binutils) is needed to read the binary's symbol versions")
    with zipfile.ZipFile(fmus[version]) as zf:
        library = next(zf.read(n) for n in zf.namelist() if n.startswith("binaries/") and n.endswith(".so"))
    needed = glibc_versions(library, tmp_path)
    assert "exp" in needed and "atan" in needed  # the table was read
    too_new = {s: v for s, v in needed.items() if v > GLIBC_LIMIT}
    assert not too_new, f"symbols needing glibc newer than {GLIBC_LIMIT}: {too_new}"
