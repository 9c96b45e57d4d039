"""Generated blocks in Markdown files: find them, fill them, tell which are stale.

A generated block sits between two HTML comments, each on a line of its own,
which neither GitHub nor MkDocs shows::

    <!-- generated: NAME [ARG ...] -->
    ...text that docgen writes...
    <!-- end generated -->

``NAME`` is a block of :data:`docgen.blocks.BLOCKS`; the arguments are passed
to it (e.g. ``<!-- generated: sweep-rates adaptive_map -->``). Everything
outside the markers is hand-written and left alone. The functions here only
transform text; reading and writing files is :mod:`docgen.__main__`'s.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass
from typing import Callable, Iterator

BEGIN = "<!-- generated: {spec} -->"
END = "<!-- end generated -->"
_BLOCK = re.compile(r"^<!-- generated: (?P<spec>[^>\n]*?) -->\n(?P<body>.*?)^<!-- end generated -->$", re.S | re.M)
_STRAY = re.compile(r"^<!-- (end )?generated", re.M)


class MarkerError(ValueError):
    """A file whose markers do not pair up (names the file and the line)."""


@dataclass(frozen=True)
class Block:
    """One generated block of a file: its name, arguments and current body."""

    name: str
    args: tuple[str, ...]
    body: str
    line: int  #: 1-based line of the opening marker

    @property
    def spec(self) -> str:
        return " ".join((self.name, *self.args))


def blocks(text: str, where: str = "<text>") -> Iterator[Block]:
    """The generated blocks of ``text``, in order; a marker without its partner is a :class:`MarkerError`."""
    end = 0
    for m in _BLOCK.finditer(text):
        _no_stray(text[end:m.start()], text, end, where)
        words = m.group("spec").split()
        if not words:
            raise MarkerError(f"{where}:{_line(text, m.start())}: generated block without a name")
        yield Block(words[0], tuple(words[1:]), m.group("body"), _line(text, m.start()))
        end = m.end()
    _no_stray(text[end:], text, end, where)


def _line(text: str, offset: int) -> int:
    return text.count("\n", 0, offset) + 1


def _no_stray(gap: str, text: str, offset: int, where: str) -> None:
    stray = _STRAY.search(gap)
    if stray:
        raise MarkerError(f"{where}:{_line(text, offset + stray.start())}: unpaired generated-block marker "
                          f"(expected `{BEGIN.format(spec='NAME')}` ... `{END}`)")


def fill(text: str, render: Callable[[Block], str], where: str = "<text>") -> str:
    """``text`` with every block's body replaced by ``render(block)`` (ending in exactly one newline)."""
    list(blocks(text, where))  # markers checked before anything is rendered

    def replace(m: re.Match) -> str:
        words = m.group("spec").split()
        block = Block(words[0], tuple(words[1:]), m.group("body"), _line(text, m.start()))
        body = render(block)
        if body != block.body:  # a renderer that keeps the body (docgen --fast) leaves it byte for byte
            body = body.rstrip("\n") + "\n"
        return f"{BEGIN.format(spec=block.spec)}\n{body}{END}"

    return _BLOCK.sub(replace, text)


def diff(old: str, new: str, where: str, context: int = 2, max_lines: int = 40) -> str:
    """A unified diff of ``old`` against ``new``, cut after ``max_lines`` lines."""
    lines = list(difflib.unified_diff(old.splitlines(), new.splitlines(), f"{where} (committed)",
                                      f"{where} (fresh)", n=context, lineterm=""))
    if len(lines) > max_lines:
        lines = lines[:max_lines] + [f"... ({len(lines) - max_lines} more diff lines)"]
    return "\n".join(lines)
