"""The planar plant's numeric kernels against what they stand for, compiled from the plant's own C source.

* The tabulated tyre curves (fmu_plant/src/tyre_curve.c) against the Magic Formula: the planar
  plant evaluates its tyre curves from tables built at initialisation (cubic Hermite, exact at the
  nodes; the formula beyond the table). ``tests/fmu/c/tyre_curve_check.c`` sweeps the slip across
  and beyond a table: the force may differ from the formula by at most 1e-8 of the peak, the slope
  dG/dq by 1e-5 of its largest value, at the corners of the parameter ranges (variables.def) and
  at the defaults.
* The small-angle turn of a kept cos/sin pair (plant_angle_turn, fmu_plant/src/model.h) against
  cos and sin: ``tests/fmu/c/angle_turn_check.c`` turns a pair by a million random steps.

Compiles two small C programs (about 1 s each; the sweeps take a few more); skipped without a C
compiler, as the FMU build would fail anyway.
"""

import itertools
import shutil
import subprocess
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "fmu_plant" / "src"
CHECKS = Path(__file__).resolve().parent / "c"

#: (B, C, E) corners: longitudinal tyre_B 0.1..100; lateral B = C_alpha / (C_y D_y) with
#: C_alpha 0.1..100, C_y 0.1..5, D_y 0.01..3, so 0.0067..1e5; C 0.1..5; E -10..1
LONGITUDINAL = [(10.0, 1.9, 0.97), *itertools.product((0.1, 10.0, 100.0), (0.1, 1.9, 5.0), (-10.0, 0.0, 1.0))]
LATERAL = [(21.92 / (1.3507 * 1.0489), 1.3507, -0.0074722),
           *itertools.product((0.0067, 15.0, 1e5), (0.1, 1.35, 5.0), (-10.0, 0.0, 1.0))]


def compiled(tmp_path_factory, name: str, *sources: str) -> Path:
    """``tests/fmu/c/<name>.c`` built with the plant's flags against its headers and ``sources``."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("a C compiler is needed to build the kernel checks")
    exe = tmp_path_factory.mktemp(name) / name
    subprocess.run([cc, "-O2", "-ffp-contract=off", f"-I{SRC}", "-o", str(exe), str(CHECKS / f"{name}.c"),
                    *(str(SRC / s) for s in sources), "-lm"], check=True)
    return exe


@pytest.fixture(scope="module")
def checker(tmp_path_factory) -> Path:
    return compiled(tmp_path_factory, "tyre_curve_check", "tyre_curve.c")


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


@pytest.mark.parametrize("max_step_rad", [1e-4, 5e-3, 0.03125, 0.1])  # sideslip, course, the series' end, beyond
def test_a_turned_pair_stays_cos_and_sin_of_its_angle(tmp_path_factory, max_step_rad):
    exe = compiled(tmp_path_factory, "angle_turn_check")
    out = subprocess.run([str(exe), "1000000", repr(max_step_rad), "7"], capture_output=True, text=True,
                         check=True).stdout
    err, err_norm = map(float, out.split())
    assert err <= 1e-12 and err_norm <= 1e-12  # a million steps: about 1e-13 of rounding's random walk
