"""NCAP- and R152-style OpenSCENARIO files written with scenariogeneration score as crd's own catalogue cells.

The files (tests/cosim/xosc_ncap.py) are written by hand with scenariogeneration,
not by crd's exporter, with the protocol's gaps and reference points at the
rear axles; a catalogue points its series at them (the ``xosc`` key). Each cell
runs with the tightening strategy and must get the same verdict, band/score and
impact speed as the bundled catalogue's cell of the same test.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

pytest.importorskip("scenariogeneration")

from cosim.matrix.catalogue import load_catalogue  # noqa: E402
from cosim.matrix.runner import run_matrix  # noqa: E402
from tests.cosim.xosc_ncap import write_case  # noqa: E402

KMH = 3.6
#: (bundled catalogue, cell id, ego km/h, target km/h, gap rule, brake)
CASES = [
    ("ncap_ccr", "CCRs-20", 20, 0, ("ttc", 6.0), None),
    ("ncap_ccr", "CCRs-50", 50, 0, ("ttc", 6.0), None),
    ("ncap_ccr", "CCRm-50", 50, 20, ("ttc", 6.0), None),
    ("ncap_ccr", "CCRb-50", 50, 50, ("headway", 1.0), (4.0, 1.0, 2.0)),
    ("r152_m1", "R152-stationary-42", 42, 0, ("ttc", 6.0), None),
]
#: row fields compared within a tolerance (the files place the bodies through other reference points, so the
#: gaps agree to rounding, not bit for bit); every other field (verdict, colour, score, contact, end,
#: interventions, ...) must be equal; the catalogue's name and the wall time differ by design
APPROX = {"impact_kmh": 0.05, "min_gap_m": 0.01, "min_speed_intervening_mps": 0.01, "sim_time_s": 0.011}
SKIPPED = ("catalogue", "wall_time_s", "impact_kmh_by_phase")


def _gap_m(ego_kmh: float, target_kmh: float, rule: tuple[str, float]) -> float:
    """Protocol gap: TTC 4 s after 2 s of steady approach (closing x 6 s), or headway x ego speed."""
    kind, value = rule
    return value * ((ego_kmh - target_kmh) / KMH if kind == "ttc" else ego_kmh / KMH)


def _catalogue(tmp: Path, bundled: str, cases: list) -> Path:
    scoring = "ncap" if bundled == "ncap_ccr" else "r152"
    lines = [f'[catalogue]\nscoring = "{scoring}"\n[sources]\nx = "NCAP/R152-style files written with '
             f'scenariogeneration"\n[targets.car]\nlength_m = 4.023\nwidth_m = 1.712\nsource = "x"\n',
             "[scenario.scenario]\nseed = 1\n[scenario.radar]\nlatency_s = 0.1\nmax_range_m = 200.0\n"]
    base = load_catalogue(bundled)
    if scoring == "ncap":
        lines.append("[scoring]\npoints = { CCRs = 1.2, CCRm = 2.4, CCRb = 1.6, CBLA = 2.0 }\nsource = \"x\"\n")
    for _, cell_id, ego, target, rule, brake in cases:
        cell = next(c for c in base.cells if c.cell_id == cell_id)
        duration = cell.scenario_dict()["scenario"]["duration_s"]
        write_case(tmp, cell_id, ego, target, _gap_m(ego, target, rule), duration, brake)
        extra = "".join(f"{k} = {str(cell.params[k]).lower()}\n" for k in ("require_no_contact", "max_impact_kmh")
                        if k in cell.params)
        lines.append(f'[[series]]\ngroup = "{cell.group}"\ntarget = "car"\nsource = "x"\nego_speed_kmh = [{ego}]\n'
                     f'target_speed_kmh = {target}\nxosc = "{cell_id}.xosc"\n{extra}')
    path = tmp / f"{bundled}_xosc.toml"
    path.write_text("\n".join(lines))
    return path


@pytest.mark.slow
@pytest.mark.parametrize("bundled", ["ncap_ccr", "r152_m1"])
def test_scenariogeneration_files_score_as_the_catalogue(tmp_path: Path, bundled: str) -> None:
    cases = [c for c in CASES if c[0] == bundled]
    ours = load_catalogue(_catalogue(tmp_path, bundled, cases))
    theirs = load_catalogue(bundled)
    theirs = dataclasses.replace(theirs, cells=tuple(c for c in theirs.cells if c.cell_id in {k[1] for k in cases}))
    rows_x, _ = run_matrix([ours], ["tightening"], workers=1)
    rows_c, _ = run_matrix([theirs], ["tightening"], workers=1)
    assert [r["cell"] for r in rows_x] == [r["cell"] for r in rows_c]
    for x, c in zip(rows_x, rows_c):
        assert x["error"] is None and c["error"] is None
        assert x.keys() == c.keys() and "verdict" in x
        exact = [k for k in x if k not in APPROX and k not in SKIPPED]
        assert {k: x[k] for k in exact} == {k: c[k] for k in exact}, x["cell"]
        for key, tol in APPROX.items():
            assert (x[key] is None) == (c[key] is None), (x["cell"], key)
            if x[key] is not None:
                assert x[key] == pytest.approx(c[key], abs=tol), (x["cell"], key)
