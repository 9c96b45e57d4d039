"""The plant's variable table, read from ``src/variables.def``.

``variables.def`` is the single source of truth for value references, names,
kinds, start values, ranges and units: the C code includes it as an X-macro,
and this module parses it so the model descriptions (``description.py``) are
generated from the same lines. A value reference is therefore typed once.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

SRC_DIR = Path(__file__).resolve().parent / "src"
TABLE_PATH = SRC_DIR / "variables.def"

_ENTRY = re.compile(
    r"^PLANT_VAR\(\s*(?P<vr>\d+),\s*(?P<name>\w+),\s*(?P<kind>\w+),\s*(?P<type>\w+),"
    r"\s*(?P<start>[^,]+),\s*(?P<lo>[^,]+),\s*(?P<hi>[^,]+),"
    r'\s*"(?P<unit>[^"]*)",\s*"(?P<description>[^"]*)"\s*\)\s*$'
)
KINDS = ("INDEPENDENT", "INPUT", "OUTPUT", "PARAMETER")
TYPES = ("REAL", "BOOL")


class VariableTableError(ValueError):
    """``variables.def`` has a line this parser (and so the C build) cannot use."""


@dataclass(frozen=True)
class PlantVariable:
    """One row of the table. ``lo``/``hi`` bound inputs (clamp) and parameters (refuse)."""

    vr: int
    name: str
    kind: str
    type: str
    start: float
    lo: float
    hi: float
    unit: str
    description: str


def _parse_line(line: str, lineno: int) -> PlantVariable:
    match = _ENTRY.match(line.strip())
    if match is None:
        raise VariableTableError(f"{TABLE_PATH.name}:{lineno}: expected a PLANT_VAR(...) entry, got {line!r}")
    fields = match.groupdict()
    if fields["kind"] not in KINDS or fields["type"] not in TYPES:
        raise VariableTableError(
            f"{TABLE_PATH.name}:{lineno}: kind must be one of {KINDS} and type one of {TYPES}, "
            f"got {fields['kind']!r} / {fields['type']!r}"
        )
    return PlantVariable(
        vr=int(fields["vr"]),
        name=fields["name"],
        kind=fields["kind"],
        type=fields["type"],
        start=float(fields["start"]),
        lo=float(fields["lo"]),
        hi=float(fields["hi"]),
        unit=fields["unit"],
        description=fields["description"],
    )


def load_table(path: Path = TABLE_PATH) -> tuple[PlantVariable, ...]:
    """Parse the table; value references and names must be unique."""
    rows = []
    for lineno, line in enumerate(path.read_text().splitlines(), start=1):
        if line.startswith("PLANT_VAR("):
            rows.append(_parse_line(line, lineno))
    for attr in ("vr", "name"):
        values = [getattr(row, attr) for row in rows]
        duplicates = sorted({v for v in values if values.count(v) > 1})
        if duplicates:
            raise VariableTableError(f"{path.name}: duplicate {attr}s {duplicates}")
    return tuple(rows)


VARIABLES: tuple[PlantVariable, ...] = load_table()
BY_NAME: dict[str, PlantVariable] = {row.name: row for row in VARIABLES}
