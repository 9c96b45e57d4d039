"""``report.md`` of a sweep: the rates per strategy, the outcome of each setting, the maps.

Everything is drawn from ``results.parquet`` alone (``crd sweep report DIR``
redraws it from an existing table; its metadata names the sweep's subject,
:mod:`cosim.sweep.subjects`, which gives the rates beyond the shared ones, each
run's outcome in words and the maps). Rates count runs with ``status = ok``;
failed runs are counted and their errors listed. Rates and maps are per
strategy, and per value of any axis whose values are not numbers
(:func:`cosim.sweep.maps.panel`).
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Any, Sequence

from .maps import METRICS, draw_maps, panel, panel_axes, panels, strategies
from .scenario_subject import SCENARIO
from .subject import SweepSubject, mean
from .subjects import subject_of
from .table import RESULTS_NAME, read_results

REPORT_NAME = "report.md"
MAX_OUTCOME_ROWS = 80


def _num(x: float | None, spec: str = ".2f") -> str:
    return "–" if x is None else format(x, spec)


def rates(rows: list[dict], subject: SweepSubject = SCENARIO, by: Sequence[str] = ()) -> list[dict[str, Any]]:
    """Per panel (strategy, and value of each ``by`` axis): runs, failed, collisions, collision rate, mean/max
    impact speed, mean invocations, and the subject's own (a scenario's: the runs in which the ECU entered FAULT
    after start-up, none in a clean sweep; a fleet's: deadlock and clearing)."""
    out = []
    for name in panels(rows, by):
        mine = [r for r in rows if panel(r, by) == name]
        ok = [r for r in mine if r["status"] == "ok"]
        hit = [r["impact_speed_mps"] or 0.0 for r in ok if r["collided"]]
        out.append({"strategy": name, "runs": len(mine), "failed": len(mine) - len(ok), "collisions": len(hit),
                    "collision_rate": len(hit) / len(ok) if ok else None, "mean_impact_speed_mps": mean(hit),
                    "max_impact_speed_mps": max(hit) if hit else None,
                    "mean_invocations": mean([r["contingency_invocations"] for r in ok]),
                    **{c.key: c.value(ok) if ok else None for c in subject.rate_columns}})
    return out


def rates_table(rows: list[dict], subject: SweepSubject = SCENARIO, by: Sequence[str] = ()) -> list[str]:
    extra = subject.rate_columns
    lines = [f"| {', '.join(['strategy', *by])} | runs | failed | collisions | collision rate "
             "| mean impact m/s (collided) | max impact m/s | mean contingency invocations | "
             + " | ".join(c.header for c in extra) + " |", "|---" * (8 + len(extra)) + "|"]
    for r in rates(rows, subject, by):
        lines.append(f"| {r['strategy']} | {r['runs']} | {r['failed']} | {r['collisions']} "
                     f"| {_num(r['collision_rate'], '.3f')} | {_num(r['mean_impact_speed_mps'])} "
                     f"| {_num(r['max_impact_speed_mps'])} | {_num(r['mean_invocations'], '.1f')} | "
                     + " | ".join(_num(r[c.key], c.fmt) for c in extra) + " |")
    return lines


def summary_table(rows: list[dict], meta: dict[str, Any]) -> list[str]:
    """The rates table of a results table: its subject's columns, a row per panel."""
    axes = [a for a in meta["axes"] if a != meta.get("strategy_axis")]
    return rates_table(rows, subject_of(meta.get("subject", "scenario")), panel_axes(rows, axes))


def outcome(row: dict, subject: SweepSubject = SCENARIO) -> str:
    """One run in words: ``collides 4.3 m/s, 4 inv`` / ``stops 1.9 m short, 21 inv`` / ``failed``."""
    return "failed" if row["status"] != "ok" else subject.outcome(row)


def _setting(row: dict, axes: Sequence[str], base: dict[str, Any], one_at_a_time: bool) -> str:
    def fmt(v):
        return f"{v:g}" if isinstance(v, float) else str(v)
    if one_at_a_time:
        changed = [f"{a} = {fmt(row[a])}" for a in axes if row.get(a) != base.get(a)]
        return ", ".join(changed) or "base (" + ", ".join(f"{a} = {fmt(base.get(a))}" for a in axes) + ")"
    return ", ".join(f"{a} = {fmt(row.get(a))}" for a in axes)


def outcomes_table(rows: list[dict], meta: dict[str, Any]) -> list[str]:
    """One line per setting of the non-strategy axes, one column per strategy (when each cell is one run)."""
    axes = [a for a in meta["axes"] if a != meta.get("strategy_axis")]
    subject = subject_of(meta.get("subject", "scenario"))
    names = strategies(rows)
    cells: dict[str, dict[str, list[dict]]] = {}
    for r in rows:
        key = _setting(r, axes, meta.get("base_values", {}), meta.get("mode") == "one_at_a_time")
        cells.setdefault(key, {}).setdefault(r["strategy"], []).append(r)
    if len(cells) > MAX_OUTCOME_ROWS or any(len(v) != 1 for c in cells.values() for v in c.values()):
        return []
    lines = ["| setting | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for key, by in cells.items():
        lines.append(f"| {key} | " + " | ".join(outcome(by[n][0], subject) if n in by else "–" for n in names)
                     + " |")
    return lines


def _failures(rows: list[dict]) -> list[str]:
    errors = Counter(r["error"] or "(no error text)" for r in rows if r["status"] != "ok")
    return [f"- {n} × `{text[:300]}`" for text, n in errors.most_common(5)]


def _header(rows: list[dict], meta: dict[str, Any], out_dir: Path) -> list[str]:
    ok = sum(r["status"] == "ok" for r in rows)
    lines = [f"# Sweep `{meta['name']}`", ""]
    if meta.get("description"):
        lines += [meta["description"], ""]
    lines += [f"- mode `{meta['mode']}`, {len(rows)} runs ({ok} ok, {len(rows) - ok} failed), sweep seed "
              f"{meta['seed']}", f"- axes: {', '.join(f'`{a}`' for a in meta['axes'])}",
              f"- base {meta.get('subject', 'scenario')} `{meta['scenario']}`; plant FMU sha256 "
              f"`{meta['fmu_sha256'][:16]}…`; crd {meta['package_version']}",
              f"- regenerate: `crd sweep {meta['source']} --out {out_dir}`; redraw: `crd sweep report {out_dir}`", ""]
    return lines


def write_report(out_dir: Path, pairs: Sequence[tuple[str, str]] | None = None) -> Path:
    """Read ``out_dir/results.parquet``, draw the maps and write ``out_dir/report.md``; returns its path."""
    out_dir = Path(out_dir)
    table, meta = read_results(out_dir / RESULTS_NAME)
    rows = table.to_pylist()
    axes = [a for a in meta["axes"] if a != meta.get("strategy_axis")]
    subject, by = subject_of(meta.get("subject", "scenario")), panel_axes(rows, axes)
    # one value at a time leaves a map's off-base cells empty: maps only when asked for
    drawn = pairs or meta["mode"] != "one_at_a_time"
    maps = draw_maps(out_dir / "maps", rows, axes, pairs, subject.map_metrics) if drawn else []
    lines = _header(rows, meta, out_dir) + ["## Rates per strategy", ""] + summary_table(rows, meta) + [""]
    outcomes = outcomes_table(rows, meta)
    if outcomes:
        lines += ["## Outcome of each setting", ""] + outcomes + [""]
    failures = _failures(rows)
    if failures:
        lines += ["## Failed runs (most frequent errors)", ""] + failures + [""]
    if maps:
        lines += ["## Maps", "", f"A panel per {', '.join(['strategy', *by])}; each cell marginalises the other "
                  "axes. Mean impact speed is over the cell's collided runs (blank: none collided).", ""]
        for metric, x, y, file in maps:
            lines += [f"### {METRICS[metric].label}: `{x}` × `{y}`", "", f"![{metric}]({file.relative_to(out_dir)})",
                      ""]
    path = out_dir / REPORT_NAME
    path.write_text("\n".join(lines))
    return path
