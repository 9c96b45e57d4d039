"""The table of generated blocks: a block's name (as its marker gives it) -> what renders it.

Two kinds: *contract* blocks render what the code declares (the DBC, the
argparse parsers, a command's output that needs no simulation) and take
milliseconds; *result* blocks run simulations (:class:`docgen.runs.Runs`) and
take seconds to minutes. Adding a block is one function and one line in
:data:`BLOCKS`.
"""

from __future__ import annotations

import contextlib
import io
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from . import can_contract, cli_reference, results
from .runs import Runs

ROOT = Path(__file__).resolve().parents[1]


@dataclass(frozen=True)
class Generator:
    """How one block is made: ``render(args, runs) -> Markdown``; ``runs_simulations`` marks a result block."""

    render: Callable[[tuple[str, ...], Runs], str]
    doc: str
    runs_simulations: bool = False


def crd_output(argv: list[str], cwd: Path | None = None) -> tuple[int, str]:
    """Exit code and output (stdout, then stderr) of ``crd ARGV`` run in this process."""
    from cosim.cli.main import main

    out, err = io.StringIO(), io.StringIO()
    here = Path.cwd()
    try:
        os.chdir(cwd or ROOT)
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(list(argv))
    finally:
        os.chdir(here)
    return code, out.getvalue() + err.getvalue()


def _command_output(args: tuple[str, ...], runs: Runs) -> str:
    code, text = crd_output(list(args))
    if code != 0:
        raise RuntimeError(f"crd {' '.join(args)} exited {code}: {text.strip()}")
    return "\n".join(["```text", f"$ crd {' '.join(args)}", text.rstrip(), "```"])


def _script_output(args: tuple[str, ...], runs: Runs) -> str:
    """What a repository script (``python PATH``) prints, run in this process; the script must print
    nothing that depends on the machine (no wall times)."""
    import runpy
    import sys

    if len(args) != 1:
        raise ValueError(f"expected one script path, got {list(args)}")
    path = ROOT / args[0]
    out = io.StringIO()
    sys.path.insert(0, str(path.parent))  # the script's own directory, as `python PATH` has it
    try:
        with contextlib.redirect_stdout(out):
            runpy.run_path(str(path), run_name="__main__")
    finally:
        sys.path.remove(str(path.parent))
    return out.getvalue().rstrip()


def _sweep_typo(args: tuple[str, ...], runs: Runs) -> str:
    """``crd sweep bad.toml`` on a copy of a bundled sweep with its first axis path misspelt."""
    from cosim.sweep.spec import bundled_sweeps

    text = bundled_sweeps()[args[0]].read_text()
    bad = text.replace(f'"{args[1]}"', f'"{args[2]}"', 1)
    if bad == text:
        raise RuntimeError(f"sweep-typo: {args[1]!r} is not an axis path of the bundled sweep {args[0]!r}")
    with tempfile.TemporaryDirectory(prefix="crd-docgen-") as tmp:
        (Path(tmp) / "bad.toml").write_text(bad)
        code, out = crd_output(["sweep", "bad.toml"], cwd=Path(tmp))
        out = out.replace(f"{Path(tmp).resolve()}/", "").replace(f"{tmp}/", "")  # as the user typed it
    return "\n".join(["```text", "$ crd sweep bad.toml", out.rstrip(), f"$ echo $?\n{code}", "```"])


def _scenarios_table() -> str:
    """The bundled scenarios: name, what its leading comment says it is, and the command that runs it."""
    from cosim.cli.scenarios import bundled_scenarios, description

    lines = ["| scenario | what it is | run it |", "|---|---|---|"]
    for path in bundled_scenarios():
        text = description(path).replace("|", "\\|")
        lines.append(f"| `{path.stem}` | {text} | `crd run {path.stem}` |")
    return "\n".join(lines)


def _fixed(render: Callable[[], str]) -> Callable[[tuple[str, ...], Runs], str]:
    def call(args: tuple[str, ...], runs: Runs) -> str:
        if args:
            raise ValueError(f"takes no arguments, got {list(args)}")
        return render()
    return call


BLOCKS: dict[str, Generator] = {
    "cli-reference": Generator(_fixed(cli_reference.render), "every crd command, its usage and arguments"),
    "cli-commands": Generator(_fixed(cli_reference.summary_table), "one line per crd command"),
    "cli-modules": Generator(_fixed(cli_reference.module_table), "crd command -> implementing module"),
    "can-bus": Generator(_fixed(can_contract.bus_summary), "the bus, the nodes and the DBC's own comment"),
    "can-messages": Generator(_fixed(can_contract.message_table), "the DBC's messages"),
    "can-signals": Generator(_fixed(can_contract.signal_tables), "every message's signals"),
    "can-fault-bits": Generator(_fixed(can_contract.fault_bits), "EcuStatus's fault bits"),
    "scenarios-table": Generator(_fixed(_scenarios_table), "the bundled scenarios and how to run them"),
    "command": Generator(_command_output, "`crd ARGS` and its output (a command that runs no simulation)"),
    "script": Generator(_script_output, "PATH: what `python PATH` prints (a deterministic script)", True),
    "sweep-typo": Generator(_sweep_typo, "SWEEP PATH TYPO: the error of a sweep file with a misspelt key path"),
    "paper-table": Generator(results.paper_table, "crd paper's table and claims ([adaptive])", True),
    "sweep-rates": Generator(results.sweep_rates, "NAME: a bundled sweep's rates per strategy", True),
    "sweep-outcomes": Generator(results.sweep_outcomes, "NAME: a one-at-a-time sweep's outcome per setting", True),
    "sweep-by-friction": Generator(results.sweep_by_friction, "NAME: collisions and top speed per road friction",
                                   True),
    "adaptive-friction": Generator(results.adaptive_friction, "the paper and a CCRs run on wetter roads", True),
    "matrix-summary": Generator(results.matrix_summary, "CATALOGUE...: crd matrix's summary lines", True),
    "matrix-table": Generator(results.matrix_table, "CATALOGUE...: crd matrix as a table, catalogue x strategy",
                              True),
}
