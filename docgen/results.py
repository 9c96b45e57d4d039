"""Result blocks: tables made from fresh simulation runs (:class:`docgen.runs.Runs`).

Each function renders what a command prints or writes, with the machine-dependent
parts (wall times, output paths, progress) left out, so that the block depends
only on the code and the bundled data. Wall times belong on the benchmarks
page, dated and with their commit.
"""

from __future__ import annotations

import dataclasses
from types import MappingProxyType
from typing import Any

from .runs import Runs

ADAPTIVE_STRATEGIES = ("none", "conservative", "tightening", "adaptive")
WET_FRICTIONS = (1.0, 0.9, 0.8, 0.6)  #: the paper scenario's road friction in the adaptive-friction table
CCRS_FRICTIONS = (1.0, 0.5)


def paper_table(args: tuple[str, ...], runs: Runs) -> str:
    """``crd paper`` (``args == ("adaptive",)``: ``--with-adaptive``): its table without the wall
    time, then each claim with PASS/FAIL and its detail, as the command prints them."""
    from cosim.cli.progress import results_table
    from cosim.results.paper_claims import evaluate, speed_trace_dance

    if args not in ((), ("adaptive",)):
        raise ValueError(f"expected no argument or 'adaptive', got {list(args)}")
    records = runs.paper(with_adaptive=bool(args))
    lines = ["```text", results_table(records, wall=False), ""]
    for claim in evaluate(records):
        lines.append(f"[{'PASS' if claim.passed else 'FAIL'}] claim {claim.number}: {claim.text}")
        lines.append(f"        {claim.detail}")
    trace = speed_trace_dance(records)
    lines += [f"[{'PASS' if trace.passed else 'FAIL'}] claim {trace.number} (reported, issue 14): {trace.text}",
              f"        {trace.detail}", "```"]
    return "\n".join(lines)


def _one(args: tuple[str, ...]) -> str:
    if len(args) != 1:
        raise ValueError(f"expected one bundled sweep name, got {list(args)}")
    return args[0]


def sweep_rates(args: tuple[str, ...], runs: Runs) -> str:
    """The "Rates per strategy" table of the sweep's ``report.md``, with its subject's columns (a fleet sweep's
    deadlock and clearing too)."""
    from cosim.sweep.report import rates_table
    from cosim.sweep.subjects import subject_of

    rows, meta = runs.sweep(_one(args))
    return "\n".join(rates_table(rows, subject_of(meta.get("subject", "scenario"))))


def sweep_outcomes(args: tuple[str, ...], runs: Runs) -> str:
    """The "Outcome of each setting" table of the sweep's ``report.md`` (a sweep with one run per setting)."""
    from cosim.sweep.report import outcomes_table

    rows, meta = runs.sweep(_one(args))
    lines = outcomes_table(rows, meta)
    if not lines:
        raise ValueError(f"sweep {args[0]!r} has no outcome table (more than one run per setting)")
    return "\n".join(lines)


def sweep_by_friction(args: tuple[str, ...], runs: Runs) -> str:
    """Per road friction (rows) and strategy (columns): collisions of all runs, and the highest speed
    any run reached (m/s), so that how far the car gets on a slippery road is stated once, generated."""
    from cosim.sweep.maps import strategies

    rows, _ = runs.sweep(_one(args))
    ok = [r for r in rows if r["status"] == "ok"]
    names = strategies(ok)
    frictions = sorted({r["plant.road_friction"] for r in ok})
    lines = ["| road friction | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for mu in frictions:
        cells = []
        for name in names:
            mine = [r for r in ok if r["strategy"] == name and r["plant.road_friction"] == mu]
            hit = [r for r in mine if r["collided"]]
            top = max(r["max_speed_mps"] for r in mine)
            cells.append(f"{len(hit)}/{len(mine)} hit, top speed {top:.1f} m/s")
        lines.append(f"| {mu:g} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _paper_on(mu: float) -> Any:
    from cosim.cli.paper import PAPER_SCENARIO
    from cosim.scenarios.loader import load_scenario

    base = load_scenario(PAPER_SCENARIO)
    return dataclasses.replace(base, plant=dataclasses.replace(base.plant, road_friction=mu))


def _ccrs(speed_mps: float, mu: float) -> Any:
    """A UN R152 / Euro NCAP CCRs-like run on the paper scenario's plant and ECU: cruising at
    ``speed_mps`` from the start (plant ``v0``) toward a stationary car target (ISO 19206-3 length
    4.023 m) 60 m ahead, 15 s."""
    base = _paper_on(mu)
    plant = dataclasses.replace(base.plant, parameters=MappingProxyType(dict(base.plant.parameters) | {"v0": speed_mps}))
    driver = dataclasses.replace(base.driver, model="cruise", set_speed_mps=speed_mps)
    obj = dataclasses.replace(base.object, position_m=60.0, length_m=4.023)
    return dataclasses.replace(base, scenario=dataclasses.replace(base.scenario, duration_s=15.0), plant=plant,
                               driver=driver, object=obj)


def _stop_time_s(record: Any) -> float:
    """First time (s) the car is at rest after its top speed."""
    t, v = record.column("time_s"), record.column("speed_mps")
    top = max(range(len(v)), key=v.__getitem__)
    return next((t[i] for i in range(top, len(v)) if v[i] <= 0.01), float("nan"))


def _outcome(record: Any) -> str:
    m = record.metrics
    if m.collided:
        return f"hits at {m.impact_speed_mps:.1f} m/s"
    if m.final_gap_m is None:
        return f"never reaches it (top speed {m.max_speed_mps:.1f} m/s)"
    return f"stops {m.final_gap_m:.1f} m short at {_stop_time_s(record):.2f} s"


def adaptive_friction(args: tuple[str, ...], runs: Runs) -> str:
    """Two tables: the paper scenario at lower road friction, and a CCRs-like run at 45 km/h, for the
    four strategies, one plant and one ECU parameter set for every row."""
    if args:
        raise ValueError(f"takes no arguments, got {list(args)}")
    lines = ["| paper scenario, road friction | " + " | ".join(ADAPTIVE_STRATEGIES) + " |",
             "|---" * (len(ADAPTIVE_STRATEGIES) + 1) + "|"]
    for mu in WET_FRICTIONS:
        cells = [_outcome(runs.scenario((_paper_on, mu, s))) for s in ADAPTIVE_STRATEGIES]
        lines.append(f"| {mu:g} | " + " | ".join(cells) + " |")
    lines += ["", "| CCRs-like, cruising at 45 km/h | " + " | ".join(ADAPTIVE_STRATEGIES) + " |",
              "|---" * (len(ADAPTIVE_STRATEGIES) + 1) + "|"]
    for mu in CCRS_FRICTIONS:
        cells = [_outcome(runs.scenario((_ccrs, 12.5, mu, s))) for s in ADAPTIVE_STRATEGIES]
        lines.append(f"| road friction {mu:g} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def matrix_summary(args: tuple[str, ...], runs: Runs) -> str:
    """``crd matrix CATALOGUE...``'s summary lines (three paper strategies, one radar phase)."""
    from cosim.matrix.report import summary_lines
    from cosim.results.paper_claims import REQUIRED

    if not args:
        raise ValueError("expected one or more catalogue names")
    catalogues, rows = runs.matrix(tuple(args), tuple(REQUIRED))
    return "\n".join(["```text", *summary_lines(catalogues, rows), "```"])


def matrix_table(args: tuple[str, ...], runs: Runs) -> str:
    """``crd matrix CATALOGUE...`` as one Markdown table: a row per catalogue, a column per paper strategy, each
    cell the cells that meet their requirement and the scoring's headline (NCAP points, interventions, contacts)."""
    import re

    from cosim.matrix.scorings import scoring_named
    from cosim.results.paper_claims import REQUIRED

    if not args:
        raise ValueError("expected one or more catalogue names")
    catalogues, rows = runs.matrix(tuple(args), tuple(REQUIRED))
    headline = re.compile(r"NCAP ([\d.]+/[\d.]+) pts|(interventions \d+)|(contacts \d+)")
    lines = ["| catalogue | " + " | ".join(f"`{s}`" for s in REQUIRED) + " |", "|---|" + "---|" * len(REQUIRED)]
    for cat in catalogues:
        cells = []
        for s in REQUIRED:
            mine = [r for r in rows if r["catalogue"] == cat.name and r["strategy"] == s]
            met = sum(bool(r["passed"]) for r in mine)
            found = headline.search(scoring_named(cat.scoring).summary(mine, cat.scoring_table))
            extra = "" if found is None else ", " + (f"{found[1]} points" if found[1] else found[2] or found[3])
            cells.append(f"{met}/{len(mine)} met{extra}")
        lines.append(f"| `{cat.name}` | " + " | ".join(cells) + " |")
    return "\n".join(lines)
