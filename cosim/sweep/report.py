"""``report.md`` of a sweep: the rates per strategy, the outcome of each setting, the maps.

Everything is drawn from ``results.parquet`` alone (``crd sweep report DIR``
redraws it from an existing table). Rates count runs with ``status = ok``;
failed runs are counted and their errors listed.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Any, Sequence

from .maps import METRICS, draw_maps, strategies
from .table import RESULTS_NAME, read_results

REPORT_NAME = "report.md"
MAX_OUTCOME_ROWS = 80


def _mean(xs: list[float]) -> float | None:
    return sum(xs) / len(xs) if xs else None


def _num(x: float | None, spec: str = ".2f") -> str:
    return "–" if x is None else format(x, spec)


def rates(rows: list[dict]) -> list[dict[str, Any]]:
    """Per strategy: runs, failed, collisions, collision rate, mean/max impact speed, mean invocations, and the
    runs in which the ECU entered FAULT after start-up (a clean sweep has none)."""
    out = []
    for name in strategies(rows):
        mine = [r for r in rows if r["strategy"] == name]
        ok = [r for r in mine if r["status"] == "ok"]
        hit = [r["impact_speed_mps"] for r in ok if r["collided"]]
        out.append({"strategy": name, "runs": len(mine), "failed": len(mine) - len(ok), "collisions": len(hit),
                    "collision_rate": len(hit) / len(ok) if ok else None, "mean_impact_speed_mps": _mean(hit),
                    "max_impact_speed_mps": max(hit) if hit else None,
                    "mean_invocations": _mean([r["contingency_invocations"] for r in ok]),
                    "runs_with_fault": sum(1 for r in ok if r.get("fault_entries"))})
    return out


def rates_table(rows: list[dict]) -> list[str]:
    lines = ["| strategy | runs | failed | collisions | collision rate | mean impact m/s (collided) "
             "| max impact m/s | mean contingency invocations | runs with FAULT |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rates(rows):
        lines.append(f"| {r['strategy']} | {r['runs']} | {r['failed']} | {r['collisions']} "
                     f"| {_num(r['collision_rate'], '.3f')} | {_num(r['mean_impact_speed_mps'])} "
                     f"| {_num(r['max_impact_speed_mps'])} | {_num(r['mean_invocations'], '.1f')} "
                     f"| {r['runs_with_fault']} |")
    return lines


def outcome(row: dict) -> str:
    """One run in words: ``collides 4.3 m/s, 4 inv`` / ``stops 1.9 m short, 21 inv`` / ``failed``."""
    if row["status"] != "ok":
        return "failed"
    inv = row["contingency_invocations"]
    if row["collided"]:
        return f"collides {row['impact_speed_mps']:.1f} m/s, {inv} inv"
    gap = row["final_gap_m"]
    return f"stops {gap:.1f} m short, {inv} inv" if gap is not None else f"no collision, {inv} inv"


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
    names = strategies(rows)
    cells: dict[str, dict[str, list[dict]]] = {}
    for r in rows:
        key = _setting(r, axes, meta.get("base_values", {}), meta.get("mode") == "one_at_a_time")
        cells.setdefault(key, {}).setdefault(r["strategy"], []).append(r)
    if len(cells) > MAX_OUTCOME_ROWS or any(len(v) != 1 for c in cells.values() for v in c.values()):
        return []
    lines = ["| setting | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for key, by in cells.items():
        lines.append(f"| {key} | " + " | ".join(outcome(by[n][0]) if n in by else "–" for n in names) + " |")
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
              f"- base scenario `{meta['scenario']}`; plant FMU sha256 `{meta['fmu_sha256'][:16]}…`; "
              f"crd {meta['package_version']}",
              f"- regenerate: `crd sweep {meta['source']} --out {out_dir}`; redraw: `crd sweep report {out_dir}`", ""]
    return lines


def write_report(out_dir: Path, pairs: Sequence[tuple[str, str]] | None = None) -> Path:
    """Read ``out_dir/results.parquet``, draw the maps and write ``out_dir/report.md``; returns its path."""
    out_dir = Path(out_dir)
    table, meta = read_results(out_dir / RESULTS_NAME)
    rows = table.to_pylist()
    axes = [a for a in meta["axes"] if a != meta.get("strategy_axis")]
    # one value at a time leaves a map's off-base cells empty: maps only when asked for
    maps = draw_maps(out_dir / "maps", rows, axes, pairs) if pairs or meta["mode"] != "one_at_a_time" else []
    lines = _header(rows, meta, out_dir) + ["## Rates per strategy", ""] + rates_table(rows) + [""]
    outcomes = outcomes_table(rows, meta)
    if outcomes:
        lines += ["## Outcome of each setting", ""] + outcomes + [""]
    failures = _failures(rows)
    if failures:
        lines += ["## Failed runs (most frequent errors)", ""] + failures + [""]
    if maps:
        lines += ["## Maps", "", "Per strategy; each cell marginalises the other axes. "
                  "Mean impact speed is over the cell's collided runs (blank: none collided).", ""]
        for metric, x, y, file in maps:
            lines += [f"### {METRICS[metric]}: `{x}` × `{y}`", "", f"![{metric}]({file.relative_to(out_dir)})", ""]
    path = out_dir / REPORT_NAME
    path.write_text("\n".join(lines))
    return path
