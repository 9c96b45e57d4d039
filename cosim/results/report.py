"""``report.md``: one page a person reads after a run.

It holds the results table, the verdicts (the paper's claims or the
scenario's ``[checks]``), the warnings and errors, links to the plots, and the
resolved configuration. Numbers are rounded to what they mean: positions and
gaps to the centimetre, speeds to 0.01 m/s, times to the 10 ms ECU cycle.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

from .run_record import RunRecord

#: event kinds the report lists one by one (the rest are counted)
LISTED_EVENTS = ("warning", "fmi_error", "collision", "ecu_lost", "second_ecu")


@dataclass(frozen=True)
class Verdict:
    """One claim or check: what was asked, whether it holds, and the measurement."""

    label: str
    passed: bool
    detail: str


def fmt(x: float | None, digits: int = 2, unit: str = "") -> str:
    """``x`` rounded to ``digits`` decimals with ``unit``; ``-`` for ``None``."""
    if x is None:
        return "-"
    return f"{round(x, digits) + 0.0:.{digits}f}" + (f" {unit}" if unit else "")  # + 0.0: no "-0.00"


def metrics_table(records: Sequence[RunRecord]) -> str:
    """The results as a Markdown table."""
    lines = ["| strategy | collided | impact speed (m/s) | min gap (m) | final gap (m) | contingency invocations"
             " | max speed (m/s) | simulated (s) | wall (s) |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in records:
        m = r.metrics
        lines.append(f"| {m.strategy} | {'yes' if m.collided else 'no'} | {fmt(m.impact_speed_mps)} |"
                     f" {fmt(m.min_gap_m)} | {fmt(m.final_gap_m)} | {m.contingency_invocations} |"
                     f" {fmt(m.max_speed_mps)} | {fmt(m.sim_time_s)} | {fmt(m.wall_time_s)} |")
    return "\n".join(lines)


def _verdicts(heading: str, verdicts: Sequence[Verdict]) -> list[str]:
    if not verdicts:
        return [f"## {heading}", "", "None stated."]
    lines = [f"## {heading}", ""]
    for v in verdicts:
        lines.append(f"- **{'PASS' if v.passed else 'FAIL'}** {v.label}  \n  {v.detail}")
    return lines


def _events(records: Sequence[RunRecord]) -> list[str]:
    lines = ["## Warnings, errors and events", ""]
    for r in records:
        listed = [e for e in r.events if e.kind in LISTED_EVENTS]
        counts = Counter(e.kind for e in r.events if e.kind not in LISTED_EVENTS)
        lines.append(f"- **{r.strategy}**" + ("" if listed or counts or r.error else ": none"))
        if r.error:
            lines.append(f"  - error: {r.error}")
        lines += [f"  - t = {e.t_s:.2f} s, {e.kind}: {e.detail}" for e in listed]
        lines += [f"  - {kind}: {n} events (`{r.strategy}/events.json`)" for kind, n in sorted(counts.items())]
    return lines


def _ecu_settings(records: Sequence[RunRecord]) -> list[str]:
    """What an ECU on a bus announced it runs, per run (nothing for an ECU in this process)."""
    announced = [(r.strategy, r.ecu_settings) for r in records if r.ecu_settings is not None]
    if not announced:
        return []
    lines = ["## ECU settings", ""]
    for strategy, e in announced:
        if not e["announced"]:
            lines.append(f"- **{strategy}** ({e['placement']}): the ECU did not announce what it runs "
                         "(`--ecu-settings ecu`): its settings are not known")
            continue
        known = f"{e['known_as']}" if e["known_as"] else "settings not known here"
        lines.append(f"- **{strategy}** ({e['placement']}, settings used: {e['source']}): the ECU runs crd "
                     f"{e['software_version']}, strategy {e['strategy']}, config digest {e['config_digest']}: {known}"
                     f" (the scenario's `[ecu]`: {e['scenario_config_digest']})")
    return lines + [""]


def write_report(path: Path, title: str, records: Sequence[RunRecord], verdicts: tuple[str, Sequence[Verdict]],
                 plots: Sequence[tuple[str, str]], resolved_toml: str) -> None:
    """Write ``report.md``: ``verdicts`` is (heading, list); ``plots`` are (caption, path relative to the report)."""
    heading, items = verdicts
    lines = [f"# {title}", "", "## Results", "", metrics_table(records), ""]
    lines += _ecu_settings(records)
    lines += _verdicts(heading, items) + [""]
    lines += _events(records) + ["", "## Plots", ""]
    lines += [f"![{caption}]({rel})\n" for caption, rel in plots]
    lines += ["## Resolved configuration", "", "`config.resolved.toml`, which `crd run` reads to repeat the run:",
              "", "```toml", resolved_toml.rstrip(), "```", ""]
    path.write_text("\n".join(lines))
