"""``crd paper``: the three strategies on paper_cyclist.toml and the paper's claims."""

import json
import re

import pytest

from cosim.cli.main import main as crd


@pytest.mark.slow
def test_crd_paper_states_every_claim(tmp_path, capsys):
    code = crd(["paper", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    for n in range(1, 6):
        assert f"claim {n}:" in out
    runs = {r["strategy"]: r for r in json.loads((tmp_path / "metrics.json").read_text())["runs"]}
    assert set(runs) == {"none", "conservative", "tightening"}
    assert (tmp_path / "speed_profiles.png").stat().st_size > 10_000
    assert not re.search(r"\d\.\d{4,}", out), out  # numbers rounded to their meaning (impact 4.28 m/s)
    report = (tmp_path / "report.md").read_text()
    for n in range(1, 6):
        assert f"claim {n}:" in report
    assert "none, conservative, tightening" in report and "](speed_profiles.png)" in report
    gating = [line for line in out.splitlines() if line.startswith("[") and "claim 3s" not in line]
    assert len(gating) == 5
    assert code == (0 if not any(line.startswith("[FAIL]") for line in gating) else 3)
    assert all(line.startswith("[PASS]") for line in gating), out  # the reproduction's goal: claims 1-5 hold
    # claim 3 judged from the speed trace (issue 14) is reported beside them; not met yet (README)
    assert "claim 3s (reported, issue 14)" in out


@pytest.mark.slow
def test_crd_paper_with_adaptive_shows_it_beside_the_three(tmp_path, capsys):
    code = crd(["paper", "--with-adaptive", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    runs = {r["strategy"]: r for r in json.loads((tmp_path / "metrics.json").read_text())["runs"]}
    assert set(runs) == {"none", "conservative", "tightening", "adaptive"}
    assert not runs["adaptive"]["collided"]
    assert code == 0 and out.count("[PASS] claim") == 5  # the claims concern the paper's three
