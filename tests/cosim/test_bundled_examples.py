"""The bundled examples do what their comments say (cosim/scenarios/car_following.toml, braking_lead.toml).

Each file's leading comment states its expectations; these tests hold the files to them, so that an
example a user copies cannot quietly turn into something else. When the ECU learns to plan with a
braking object, ``test_braking_lead_defeats_every_strategy_today`` fails: then update the example's
comment, its ``[checks]``, the README's limits and this test together.
"""

from __future__ import annotations

import dataclasses

import pytest

from cosim.cli.main import main as crd
from cosim.cli.scenarios import find_scenario
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import run_scenario
from cosim.scenarios.loader import load_scenario

STRATEGIES = ("none", "conservative", "tightening", "adaptive")


def _runs(name: str, change=None) -> dict:
    scenario = load_scenario(find_scenario(name))
    if change is not None:
        scenario = change(scenario)
    fmu = resolve_fmu(scenario)
    return {s: run_scenario(scenario, fmu, s) for s in STRATEGIES}


def _after(record, t_s: float, column: str) -> list:
    return [x for t, x in zip(record.column("time_s"), record.column(column)) if t >= t_s]


@pytest.mark.slow
def test_car_following_no_contact_tightening_settles_behind_without_contingency():
    runs = _runs("car_following")
    for strategy, record in runs.items():
        assert not record.metrics.collided, strategy
        assert min(_after(record, 1.0, "speed_mps")) > 15.0, strategy  # held near the lead's 20 m/s, never stopped
    tight = runs["tightening"]
    assert tight.metrics.contingency_invocations == 0
    assert "TIGHTENING" in tight.column("ecu_mode")
    gaps = _after(tight, 20.0, "gap_m")
    assert 2.0 < min(gaps) and max(gaps) < 5.0  # settled 2-4 m behind, as the comment says
    assert 19.0 < sum(_after(tight, 20.0, "speed_mps")) / len(gaps) < 21.0  # at about the lead's speed
    none = runs["none"]
    assert none.metrics.contingency_invocations >= 10  # the dance with a moving object
    assert none.metrics.min_gap_m < tight.metrics.min_gap_m


@pytest.mark.slow
def test_braking_lead_defeats_every_strategy_today(tmp_path):
    for strategy, record in _runs("braking_lead").items():
        assert record.metrics.collided, strategy
        assert record.metrics.impact_speed_mps > 3.0, strategy
    assert crd(["run", "braking_lead", "--out", str(tmp_path / "o")]) == 3  # its no_collision check fails


@pytest.mark.slow
def test_braking_lead_from_40_m_is_avoided():
    """The boundary the comment states: the same test from the protocol's other headway, 40 m."""
    def at_40_m(scenario):
        lead = dataclasses.replace(scenario.objects[0], position_m=40.0)
        return dataclasses.replace(scenario, objects=(lead,))

    runs = _runs("braking_lead", at_40_m)
    for strategy in ("tightening", "adaptive"):
        assert not runs[strategy].metrics.collided, strategy
        assert runs[strategy].metrics.final_gap_m > 2.0, strategy
