"""Writers for a run's outputs (``--out DIR``).

* ``metrics.json``: ``{"runs": [...], "provenance": {...}}``;
* ``<strategy>/timeseries.csv`` (one row per 10 ms ECU cycle) and the CAN logs are
  streamed while the run goes by :class:`cosim.results.stream.RunStream`, which uses
  :func:`timeseries_cells` here and :mod:`cosim.results.can_logs`;
* ``<strategy>/events.json``: gateway fallbacks, collision, FMI error;
* ``config.resolved.toml``: every resolved value, loadable by ``crd run``;
  its header and ``metrics.json`` carry the FMU's sha256, the package version
  and the seed.
"""

from __future__ import annotations

import csv
import io
import json
import functools
import math
import os
import tempfile
from dataclasses import fields
from importlib.metadata import PackageNotFoundError, version
from itertools import chain
from pathlib import Path
from typing import Iterable, Sequence

from .events import event_counts
from .run_record import TIMESERIES_COLUMNS, RunRecord
from ..scenarios.config import Scenario
from ..scenarios.resolve import DERIVED_ECU_KEYS, scenario_to_dict
from ..scenarios.toml_writer import dumps


def package_version() -> str:
    try:
        return version("crd")
    except PackageNotFoundError:
        return "unknown"


def provenance(scenario: Scenario, records: Iterable[RunRecord]) -> dict:
    """Where the results come from; with an ECU on a bus, also what it announced it runs (``ecu_settings``)."""
    records = list(records)
    prov = {
        "package_version": package_version(),
        "seed": scenario.scenario.seed,
        "fmu_path": records[0].fmu_path if records else "",
        "fmu_sha256": records[0].fmu_sha256 if records else "",
        "fmi_version": scenario.plant.fmi_version if scenario.plant.fmu == "builtin" else None,
    }
    if records and records[0].ecu_settings is not None:
        prov["ecu_settings"] = records[0].ecu_settings
    return prov


def _finite(x):
    return None if isinstance(x, float) and not math.isfinite(x) else x


def write_metrics(path: Path, records: Iterable[RunRecord], prov: dict, status: str = "complete",
                  error: str | None = None) -> None:
    """``metrics.json``, replaced in one step; ``status``: running, complete, interrupted or error
    (an exception, or a run that stopped on an error; each run has its own ``status`` too).

    Written before the first run (``running``), after each run, and on every way out of
    :func:`cosim.loop.experiment.run_strategies`, so it always says how far the invocation got.
    """
    runs = []
    for r in records:
        entry = {k: _finite(v) for k, v in r.metrics.as_dict().items()}
        entry["error"] = r.error
        entry.update(run_status(r))
        if r.ecu_settings is not None:  # an ECU on a bus: what it runs (in process: the resolved config's [ecu])
            entry["ecu_settings"] = r.ecu_settings
        if r.contact is not None:
            entry["contact"] = r.contact
        runs.append(entry)
    write_json_atomic(path, {"status": status, "error": error, "runs": runs, "provenance": prov})


def write_json_atomic(path: Path, data: object) -> None:
    """``data`` as indented JSON at ``path``, replaced in one step (never half written)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        umask = os.umask(0o022)
        os.umask(umask)
        os.fchmod(fd, 0o666 & ~umask)  # as open() would create it (mkstemp makes it 0600)
        with os.fdopen(fd, "w") as handle:
            handle.write(json.dumps(data, indent=2) + "\n")
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def run_status(record: RunRecord) -> dict:
    """``status`` (ok, collided, error, interrupted), the signal of an interrupt and the events by kind."""
    return {"status": record.status, "interrupted_by": record.interrupted, "event_counts": event_counts(record)}


def timeseries_cells(row: tuple) -> list:
    """One time-series row as CSV cells: time to 1 ms, other floats to 6 significant digits."""
    return [f"{v:.6g}" if isinstance(v, float) and k else (f"{v:.3f}" if k == 0 else v) for k, v in enumerate(row)]


_QUOTED = frozenset(',"\r\n')


@functools.lru_cache(maxsize=16)
def _row_line(columns: tuple[str, ...]) -> str:
    """One time-series row of ``columns`` as :func:`timeseries_cells` and ``csv.writer`` (excel dialect) make it,
    when every cell but the mode is a float and the mode a plain word (a ``%`` per row: 2.6 instead of 8.7 µs)."""
    return "%.3f," + ",".join("%s" if name == "ecu_mode" else "%.6g" for name in columns[1:]) + "\r\n"


def timeseries_lines(rows: Sequence[tuple], columns: tuple[str, ...] = TIMESERIES_COLUMNS) -> str:
    """``rows`` as CSV text, exactly as ``csv.writer(...).writerow(timeseries_cells(row))`` writes each."""
    mode_column = columns.index("ecu_mode")
    modes = {row[mode_column] for row in rows}
    plain = (set(map(type, chain.from_iterable(rows))) <= {float, str}
             and all(type(m) is str and _QUOTED.isdisjoint(m) for m in modes))
    if plain:
        try:
            line = _row_line(columns)
            return "".join([line % row for row in rows])
        except TypeError:  # e.g. a word in a number's column: csv's way below
            pass
    text = io.StringIO(newline="")
    writer = csv.writer(text)
    for row in rows:
        writer.writerow(timeseries_cells(row))
    return text.getvalue()


def write_timeseries(path: Path, record: RunRecord) -> None:
    with open(path, "w", newline="") as handle:
        csv.writer(handle).writerow(record.columns)
        handle.write(timeseries_lines(record.rows, record.columns))


def write_events(path: Path, record: RunRecord) -> None:
    events = [{"t_s": e.t_s, "kind": e.kind, "detail": e.detail, **(e.data or {})} for e in record.events]
    path.write_text(json.dumps({"events": events, "error": record.error}, indent=2) + "\n")


def write_resolved_config(path: Path, scenario: Scenario, ecu_config, prov: dict) -> None:
    """``config.resolved.toml``; its ``[ecu]`` is what the ECU ran: an attached ECU's own settings when the run
    used them (``--ecu-settings ecu``), as far as they are known (:func:`_ecu_table`)."""
    data = scenario_to_dict(scenario, strategy=ecu_config.strategy)
    data["ecu"].update({f.name: getattr(ecu_config, f.name) for f in fields(ecu_config)
                        if f.init and f.name not in DERIVED_ECU_KEYS})
    header = [
        "Resolved scenario: every value used by the run (defaults included); `crd run` reads it.",
        f"package version: {prov['package_version']}",
        f"seed: {prov['seed']}",
        f"plant FMU: {prov['fmu_path']}",
        f"plant FMU sha256: {prov['fmu_sha256']}",
    ]
    announced = prov.get("ecu_settings")
    if announced is not None and announced["source"] != "scenario":
        data["ecu"], note = _ecu_table(announced, data["ecu"])
        header.append(note)
    path.write_text(dumps(data, header="\n".join(header)))


def _ecu_table(announced: dict, scenario_ecu: dict) -> tuple[dict, str]:
    """The ``[ecu]`` an ECU that used its own settings ran, and a header line saying where it comes from."""
    if not announced["announced"]:
        return {}, "[ecu]: the ECU's own settings, which it did not announce (--ecu-settings ecu): not known here"
    what = f"config digest {announced['config_digest']}, crd {announced['software_version']}"
    if announced["settings"] is None:
        return {"strategy": announced["strategy"]}, (
            f"[ecu]: the ECU's own settings ({what}), not known here: only its strategy is given")
    table = {"strategy": announced["strategy"], **{k: v for k, v in announced["settings"].items() if k != "strategy"}}
    for key in ("sim_time", "key_file"):  # not in the digest: as the run set them
        if key in scenario_ecu:
            table[key] = scenario_ecu[key]
    return table, f"[ecu]: the ECU's own settings, {announced['known_as']} ({what})"

