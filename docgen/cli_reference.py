"""The CLI reference, rendered from the ``crd`` command's own argparse parsers.

Every subcommand registers its parser in :data:`cosim.cli.main.SUBCOMMANDS`;
this module builds the whole parser tree (as ``crd --help`` would, with every
subcommand loaded) and writes, per command and nested action, its help, its
usage line and a table of its arguments. The usage is wrapped at a fixed
width, so the page does not depend on the terminal that renders it.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Iterator

from cosim.cli.main import SUBCOMMANDS, _build_parser

WIDTH = 100
ROOT = Path(__file__).resolve().parents[1]


def _formatter(prog: str) -> argparse.HelpFormatter:
    return argparse.HelpFormatter(prog, width=WIDTH)


def _fixed_width(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    parser.formatter_class = _formatter
    return parser


def _subparsers(parser: argparse.ArgumentParser) -> argparse._SubParsersAction | None:
    return next((a for a in parser._actions if isinstance(a, argparse._SubParsersAction)), None)


def commands(parser: argparse.ArgumentParser | None = None) -> Iterator[tuple[str, str, argparse.ArgumentParser]]:
    """``(prog, help, parser)`` of every command and nested action, depth first, in registration order."""
    parser = parser or _build_parser([])
    sub = _subparsers(parser)
    if sub is None:
        return
    helps = {a.dest: a.help or "" for a in sub._choices_actions}
    for name, child in sub.choices.items():
        yield child.prog, helps.get(name, ""), _fixed_width(child)
        yield from commands(child)


def _cell(text: object) -> str:
    return " ".join(str(text).split()).replace("|", "\\|")


def _argument(action: argparse.Action) -> str:
    if not action.option_strings:
        return f"`{action.metavar or action.dest}`"
    metavar = ""
    if action.nargs != 0:
        metavar = " " + (action.metavar if isinstance(action.metavar, str) else action.dest.upper())
        if action.choices is not None:
            metavar = " {" + ",".join(map(str, action.choices)) + "}"
    return ", ".join(f"`{flag}{metavar}`" for flag in action.option_strings)


def _default(action: argparse.Action) -> str:
    if action.nargs == 0 or action.default in (None, argparse.SUPPRESS, False) or action.required:
        return ""
    if isinstance(action.default, list) and not action.default:
        return ""
    default = action.default
    if isinstance(default, Path) and default.is_absolute() and default.is_relative_to(ROOT):
        default = default.relative_to(ROOT)  # the repository's file, not this checkout's path
    return f"`{default}`"


def argument_table(parser: argparse.ArgumentParser) -> list[str]:
    """``| argument | default | help |`` for every argument but ``--help`` and nested actions."""
    rows = []
    for action in parser._actions:
        if isinstance(action, (argparse._HelpAction, argparse._SubParsersAction)) or action.help == argparse.SUPPRESS:
            continue
        help_text = (action.help or "") % {"default": action.default, "prog": parser.prog} if action.help else ""
        rows.append(f"| {_argument(action)} | {_default(action)} | {_cell(help_text)} |")
    if not rows:
        return []
    return ["| argument | default | help |", "|---|---|---|", *rows]


def render() -> str:
    """Every ``crd`` command: heading, help, usage, arguments."""
    top = _fixed_width(_build_parser([]))
    lines = [f"`crd` has {len(SUBCOMMANDS)} commands; `crd COMMAND --help` prints the same text.", "",
             "```text", top.format_usage().strip(), "```", ""]
    lines += argument_table(top) + [""]
    for prog, help_text, parser in commands(top):
        depth = prog.count(" ")
        lines += [f"{'#' * (depth + 1)} `{prog}`", ""]
        if help_text:
            lines += [help_text[0].upper() + help_text[1:] + ("" if help_text.endswith(".") else "."), ""]
        if parser.description:
            lines += [parser.description.strip(), ""]
        lines += ["```text", parser.format_usage().strip(), "```", ""]
        table = argument_table(parser)
        lines += table + [""] if table else []
    return "\n".join(lines)


def summary_table() -> str:
    """One row per top-level command: ``crd NAME`` and its help (the README's command list)."""
    lines = ["| command | what it does |", "|---|---|"]
    for prog, help_text, _ in commands():
        if prog.count(" ") == 1:
            lines.append(f"| `{prog}` | {_cell(help_text)} |")
    return "\n".join(lines)


def module_table() -> str:
    """``crd NAME`` and the module that implements it (docs/CONTRACTS.md)."""
    return "\n".join(["| command | module |", "|---|---|"]
                     + [f"| `crd {name}` | `{module}` |" for name, module in SUBCOMMANDS.items()])
