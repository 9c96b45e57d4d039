"""``crd matrix``'s report reads at a glance: a verdict and a margin in every cell, band counts beside
the requirement count, a legend on the band plot, nothing abbreviated (no simulation: rows made here)."""

from __future__ import annotations

from cosim.matrix.catalogue import load_catalogue
from cosim.matrix.report import band_grid, band_legend, cell_table, report_text, summary_lines
from cosim.matrix.scoring import Outcome
from cosim.matrix.scorings import score_cell, scoring_named


def _row(cat, cell, strategy="none", impact=0.0, gap=2.6, interventions=0, low=None):
    row = {"catalogue": cat.name, "scoring": cat.scoring, "cell": cell.cell_id, "group": cell.group,
           "test_speed_kmh": cell.ego_speed_kmh, "strategy": strategy, "collided": impact > 0.0,
           "impact_kmh": impact, "min_gap_m": None if impact > 0.0 else gap, "interventions": interventions,
           "min_speed_intervening_mps": low, "error": None}
    row.update(scoring_named(cat.scoring).row_fields(cell.params))
    outcome = Outcome(impact > 0.0, impact, interventions, low, row["min_gap_m"], None, 1.0, 0.1)
    row.update(score_cell(cat.scoring, cell.params, outcome))
    return row


def _cell(cat, group, speed_kmh):
    return next(c for c in cat.cells if c.group == group and c.ego_speed_kmh == speed_kmh)


def test_r152_cells_lead_with_the_verdict_and_give_the_margin():
    cat = load_catalogue("r152_m1")
    text = scoring_named("r152").cell_text
    assert text(_row(cat, cat.cells[0])) == "PASS no contact (min gap 2.6 m)"
    limit_0 = next(c for c in cat.cells if c.params["max_impact_kmh"] == 0)
    assert text(_row(cat, limit_0, impact=7.5)) == "**FAIL** 7.5 km/h (7.5 over 0 km/h)"
    limit_35 = next(c for c in cat.cells if c.params["max_impact_kmh"] == 35)
    assert text(_row(cat, limit_35, impact=7.9)) == "PASS 7.9 km/h (27.1 under 35 km/h)"


def test_ncap_red_cell_is_red_and_says_by_how_much_and_summary_counts_the_bands():
    cat = load_catalogue("ncap_ccr")
    ccrs_10 = _cell(cat, "CCRs", 10)
    ccrb = next(c for c in cat.cells if c.group == "CCRb")
    text = scoring_named("ncap").cell_text
    red = _row(cat, ccrb, impact=39.7)
    assert red["passed"] and text(red) == "red 39.7 km/h (9.7 over 30 km/h)"
    yellow = _row(cat, ccrb, impact=5.7)
    assert text(yellow) == "yellow 5.7 km/h (4.3 under 10 km/h)"
    required = _row(cat, ccrs_10, impact=3.0)
    assert text(required) == "**FAIL** (avoidance required) yellow 3.0 km/h (7.0 under 10 km/h)"
    green = _row(cat, ccrs_10)
    assert text(green) == "green no contact (min gap 2.6 m)"

    rows = [_row(cat, c, impact=39.7 if c.group == "CCRb" else 0.0) for c in cat.cells]
    (line,) = summary_lines([cat], rows)
    n_ccrb = sum(c.group == "CCRb" for c in cat.cells)
    assert f"{len(rows)}/{len(rows):<3} requirements met" in line
    assert f"bands: {len(rows) - n_ccrb} green, 0 yellow, 0 orange, 0 brown, {n_ccrb} red" in line


def test_false_positive_and_follow_spell_out_their_figures():
    fp = load_catalogue("false_positive")
    text = scoring_named("false_positive").cell_text
    assert text(_row(fp, fp.cells[0])) == "PASS 0 interventions"
    assert text(_row(fp, fp.cells[0], interventions=1)) == "**FAIL** 1 intervention"
    table = "\n".join(cell_table(fp, [_row(fp, c, interventions=2) for c in fp.cells]))
    assert "int." not in table and "**FAIL** 2 interventions" in table

    follow = load_catalogue("follow")
    text = scoring_named("follow").cell_text
    assert text(_row(follow, follow.cells[0], low=1.3)) == "PASS min 1.3 m/s (0.3 over 1 m/s)"
    assert text(_row(follow, follow.cells[0], low=0.4)) == "**FAIL** min 0.4 m/s (0.6 under 1 m/s)"
    assert text(_row(follow, follow.cells[0], impact=7.8)) == "**FAIL** contact at 7.8 km/h"
    assert text(_row(follow, follow.cells[0])) == "PASS no intervention"


def test_report_explains_each_catalogues_cells():
    cats = [load_catalogue(n) for n in ("r152_m1", "ncap_ccr", "false_positive", "follow")]
    rows = [_row(cat, c) for cat in cats for c in cat.cells]
    meta = {"strategies": ["none"], "phases": 1, "runs": len(rows), "wall_s": 1.0, "workers": 1, "version": "x"}
    text = report_text(cats, rows, meta, {})
    for name in ("r152", "ncap", "false_positive", "follow"):
        assert f"How to read a cell: {scoring_named(name).rule}" in text
    assert " pass\n" not in text and "requirements met" in text


def test_band_plot_has_a_legend_of_every_band(tmp_path):
    labels = [p.get_label() for p in band_legend()]
    assert labels == ["green: no contact", "yellow: 0-10 km/h", "orange: 10-20 km/h", "brown: 20-30 km/h",
                      "red: > 30 km/h"]
    cat = load_catalogue("ncap_ccr")
    rows = [_row(cat, c) for c in cat.cells]
    assert band_grid(tmp_path / "bands.png", cat, rows) == "bands.png"
    assert (tmp_path / "bands.png").stat().st_size > 1000
