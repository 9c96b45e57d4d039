"""``crd matrix`` end to end: outputs, exit status, and the closed-loop figures the ECU must meet."""

import csv
import json

import pytest

from cosim.cli.main import main as crd
from cosim.matrix.catalogue import load_catalogue
from cosim.matrix.runner import run_matrix

TINY = '''
[catalogue]
title = "tiny"
scoring = "r152"
[sources]
t = "test"
[targets.car]
length_m = 4.023
width_m = 1.712
source = "t"
[scenario.radar]
latency_s = 0.1
[[series]]
group = "s"
target = "car"
ego_speed_kmh = [20, 60]
max_impact_kmh = [0, {limit60}]
source = "t"
'''


@pytest.mark.slow
@pytest.mark.parametrize("limit60, code", [(35, 0), (0, 3)])
def test_crd_matrix_writes_outputs_and_exits_3_on_a_failed_requirement(tmp_path, capsys, limit60, code):
    cat = tmp_path / "tiny.toml"
    cat.write_text(TINY.format(limit60=limit60))
    out = tmp_path / "out"
    assert crd(["matrix", str(cat), "--strategy", "none", "--out", str(out)]) == code
    rows = list(csv.DictReader(open(out / "matrix.csv")))
    assert [(r["cell"], r["strategy"]) for r in rows] == [("s-20", "none"), ("s-60", "none")]
    assert rows[1]["collided"] == "True" and 0.0 < float(rows[1]["impact_kmh"]) < 35.0  # none hits at 60
    assert json.loads((out / "matrix.json").read_text())["rows"][1]["passed"] is (code == 0)
    report = (out / "report.md").read_text()
    assert "| s-60 |" in report and (out / "impact_tiny.png").is_file()
    assert "tiny             none" in capsys.readouterr().out


@pytest.mark.slow
def test_tightening_no_false_positive_and_no_standstill_behind_moving_targets():
    cats = [load_catalogue("false_positive"), load_catalogue("follow")]
    rows, _ = run_matrix(cats, ["tightening"], phases=1, workers=2)
    fp = [r for r in rows if r["scoring"] == "false_positive"]
    assert [r["cell"] for r in fp if r["interventions"] or r["collided"]] == []
    follow = [r for r in rows if r["scoring"] == "follow"]
    assert all(not r["collided"] and r["min_speed_intervening_mps"] > 1.0 for r in follow), follow


@pytest.mark.slow
def test_tightening_meets_r152_and_ccrs_avoidance_at_three_radar_phases():
    """Issue 11's figure: every R152 M1 cell and every CCRs cell <= 20 km/h, worst of 3 phases."""
    import dataclasses
    ncap = load_catalogue("ncap_ccr")
    ccrs = dataclasses.replace(ncap, cells=tuple(c for c in ncap.cells if c.cell_id in ("CCRs-10", "CCRs-20")))
    rows, _ = run_matrix([load_catalogue("r152_m1"), ccrs], ["tightening"], phases=3, workers=2)
    assert len(rows) == 15 and all(r["phases"] == 3 for r in rows)
    assert [r["cell"] for r in rows if not r["passed"]] == []
    assert all(r["colour"] == "green" for r in rows if r["scoring"] == "ncap")
