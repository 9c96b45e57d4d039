"""``python -m docgen``: re-create every generated block and page of the documentation.

::

    python -m docgen             # rewrite every stale block (README.md, docs/**/*.md) and page
    python -m docgen --check     # change nothing; exit 1 naming each stale block, with its diff
    python -m docgen --fast      # only the blocks that run no simulation (with or without --check)
    python -m docgen --list      # every block in the files, and what renders it

Whole pages rendered elsewhere are re-created too (:data:`PAGES`: the scenario
reference, rendered by :mod:`cosim.scenarios.reference`). A block whose
renderer fails stops the command with the file, the line and the error.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Callable

from .blocks import BLOCKS, ROOT
from .markers import Block, MarkerError, blocks, diff, fill
from .runs import Runs


def _scenario_reference() -> str:
    from cosim.scenarios.reference import render

    return render()


#: whole pages rendered by a function of the code (relative path -> renderer)
PAGES: dict[str, Callable[[], str]] = {"docs/scenario-reference.md": _scenario_reference}


def markdown_files(root: Path = ROOT) -> list[Path]:
    """The files that may hold generated blocks: README.md and every page under docs/."""
    return [root / "README.md", *sorted((root / "docs").rglob("*.md"))]


class BlockError(RuntimeError):
    """A block that cannot be rendered (unknown name, bad arguments, or its renderer failed)."""


def _renderer(runs: Runs, fast: bool, where: str, timings: dict[str, float]) -> Callable[[Block], str]:
    def render(block: Block) -> str:
        gen = BLOCKS.get(block.name)
        if gen is None:
            raise BlockError(f"{where}:{block.line}: unknown generated block {block.name!r} "
                             f"(known: {', '.join(sorted(BLOCKS))})")
        if fast and gen.runs_simulations:
            return block.body
        t0 = time.perf_counter()
        try:
            text = gen.render(block.args, runs)
        except Exception as exc:
            raise BlockError(f"{where}:{block.line}: block `{block.spec}`: {exc}") from exc
        timings[f"{where}:{block.line} {block.spec}"] = time.perf_counter() - t0
        return text
    return render


def regenerate(check: bool, fast: bool = False, root: Path = ROOT, runs: Runs | None = None,
               timings: dict[str, float] | None = None) -> list[str]:
    """Render every block and page; write the changed files unless ``check``. Returns one report per
    stale block or page (its place and diff), empty when everything is current."""
    stale: list[str] = []
    timings = {} if timings is None else timings
    with (runs or Runs()) as runs:
        for path in markdown_files(root):
            where = str(path.relative_to(root))
            if where in PAGES:
                fresh = PAGES[where]()
                old = path.read_text()
                if fresh != old:
                    stale.append(f"{where} (whole page)\n{diff(old, fresh, where)}")
                    if not check:
                        path.write_text(fresh)
                continue
            old = path.read_text()
            fresh = fill(old, _renderer(runs, fast, where, timings), where)
            if fresh != old:
                stale += _stale_blocks(old, fresh, where)
                if not check:
                    path.write_text(fresh)
    return stale


def _stale_blocks(old: str, fresh: str, where: str) -> list[str]:
    return [f"{where}:{a.line}: block `{a.spec}`\n{diff(a.body, b.body, where)}"
            for a, b in zip(blocks(old, where), blocks(fresh, where)) if a.body != b.body]


def _list(root: Path) -> None:
    for path in markdown_files(root):
        where = path.relative_to(root)
        if str(where) in PAGES:
            print(f"{where}: whole page")
            continue
        for block in blocks(path.read_text(), str(where)):
            gen = BLOCKS.get(block.name)
            kind = "unknown!" if gen is None else ("runs" if gen.runs_simulations else "fast")
            print(f"{where}:{block.line}: {block.spec}  [{kind}] {gen.doc if gen else ''}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m docgen", description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if a block is stale")
    parser.add_argument("--fast", action="store_true", help="only the blocks that run no simulation")
    parser.add_argument("--list", action="store_true", help="list the generated blocks")
    parser.add_argument("--times", action="store_true", help="print each block's render time")
    args = parser.parse_args(argv)
    if args.list:
        _list(ROOT)
        return 0
    timings: dict[str, float] = {}
    try:
        stale = regenerate(args.check, args.fast, root=ROOT, timings=timings)
    except (MarkerError, BlockError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    if args.times:
        for name, seconds in timings.items():
            print(f"{seconds:7.2f} s  {name}", file=sys.stderr)
    for report in stale:
        print(report if args.check else report.splitlines()[0], end="\n\n" if args.check else "\n")
    if args.check and stale:
        print(f"{len(stale)} generated block(s) stale: run `python -m docgen` and commit the result",
              file=sys.stderr)
        return 1
    print(f"{'checked' if args.check else 'regenerated'}: {len(stale)} block(s) "
          f"{'stale' if args.check else 'changed'}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
