"""The tabulated tyre curves (fmu_plant/src/tyre_curve.c) against the Magic Formula they tabulate.

The planar plant evaluates its tyre curves from tables built at initialisation (cubic Hermite,
exact at the nodes; the formula beyond the table). ``tests/fmu/c/tyre_curve_check.c`` builds a
table from the plant's own C source and sweeps the slip across and beyond it: the force may
differ from the formula by at most 1e-8 of the peak, the slope dG/dq by 1e-5 of its largest
value, at the corners of the parameter ranges (variables.def) and at the defaults. Compiles one
small C program (about 1 s; the sweeps take a few more); skipped without a C compiler, as the FMU build would fail anyway.
"""

import itertools
import shutil
import subprocess
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "fmu_plant" / "src"
CHECK = Path(__file__).resolve().parent / "c" / "tyre_curve_check.c"

#: (B, C, E) corners: longitudinal tyre_B 0.1..100; lateral B = C_alpha / (C_y D_y) with
#: C_alpha 0.1..100, C_y 0.1..5, D_y 0.01..3, so 0.0067..1e5; C 0.1..5; E -10..1
LONGITUDINAL = [(10.0, 1.9, 0.97), *itertools.product((0.1, 10.0, 100.0), (0.1, 1.9, 5.0), (-10.0, 0.0, 1.0))]
LATERAL = [(21.92 / (1.3507 * 1.0489), 1.3507, -0.0074722),
           *itertools.product((0.0067, 15.0, 1e5), (0.1, 1.35, 5.0), (-10.0, 0.0, 1.0))]


@pytest.fixture(scope="module")
def checker(tmp_path_factory) -> Path:
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("a C compiler is needed to build the tyre-curve check")
    exe = tmp_path_factory.mktemp("tyre_curve") / "tyre_curve_check"
    subprocess.run([cc, "-O2", "-ffp-contract=off", f"-I{SRC}", "-o", str(exe), str(CHECK),
                    str(SRC / "tyre_curve.c"), "-lm"], check=True)
    return exe


def errors(checker: Path, shape: tuple[float, float, float], slip_angle: bool) -> tuple[float, float, float]:
    out = subprocess.run([str(checker), *map(repr, shape), str(int(slip_angle))], capture_output=True, text=True,
                         check=True).stdout
    err_g, err_slope, table_end = map(float, out.split())
    return err_g, err_slope, table_end


@pytest.mark.parametrize("slip_angle, shapes", [(False, LONGITUDINAL), (True, LATERAL)],
                         ids=["longitudinal", "lateral"])
def test_the_table_is_the_formula_within_its_bound(checker, slip_angle, shapes):
    worst = {}
    for shape in shapes:
        err_g, err_slope, table_end = errors(checker, shape, slip_angle)
        assert table_end > 0.0
        worst[shape] = (err_g, err_slope)
    bad = {s: e for s, e in worst.items() if not (e[0] <= 1e-8 and e[1] <= 1e-5)}
    assert not bad, f"table differs from the formula beyond 1e-8 (force) / 1e-5 (slope): {bad}"


def test_the_defaults_use_the_table_over_every_braking_slip(checker):
    """With the default tyres the longitudinal table spans the slip ratio to 1 and the lateral one
    to tan(alpha) near 1, so normal driving never falls back to the formula."""
    assert errors(checker, LONGITUDINAL[0], False)[2] == 1.0
    assert errors(checker, LATERAL[0], True)[2] > 0.95
