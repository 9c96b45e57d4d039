"""The documentation's generated blocks are what the code gives today (python -m docgen --check).

A changed result, a new CLI option or a new DBC signal fails here until ``python -m docgen`` has
rewritten the blocks and the change is committed with them.
"""

from __future__ import annotations

import pytest

from docgen.__main__ import BlockError, main, regenerate
from docgen.blocks import BLOCKS
from docgen.markers import MarkerError, blocks, fill


def _stale_message(stale: list[str]) -> str:
    return "\n\n".join(stale) + "\n\nstale generated documentation: run `python -m docgen` and commit the result"


def test_contract_blocks_are_current():
    """The CAN contract, the CLI reference, the scenario reference, command outputs: no simulation."""
    stale = regenerate(check=True, fast=True)
    assert not stale, _stale_message(stale)


@pytest.mark.slow
def test_result_blocks_are_current():
    """Every results table and pasted output, from fresh runs (the paper, the bundled sweeps, the
    catalogues, the adaptive-friction runs, the dance candidates)."""
    stale = regenerate(check=True)
    assert not stale, _stale_message(stale)


def _tree(tmp_path, readme: str, page: str = "# page\n"):
    (tmp_path / "docs").mkdir()
    (tmp_path / "README.md").write_text(readme)
    (tmp_path / "docs" / "page.md").write_text(page)
    return tmp_path


def test_check_names_a_stale_block_and_the_write_mode_fixes_it(tmp_path):
    stale_readme = "intro\n<!-- generated: cli-modules -->\nold text\n<!-- end generated -->\nhand-written\n"
    root = _tree(tmp_path, stale_readme)
    (report,) = regenerate(check=True, fast=True, root=root)
    assert report.startswith("README.md:2: block `cli-modules`") and "-old text" in report
    assert (root / "README.md").read_text() == stale_readme  # check mode writes nothing
    assert len(regenerate(check=False, fast=True, root=root)) == 1
    text = (root / "README.md").read_text()
    assert text.startswith("intro\n<!-- generated: cli-modules -->\n| command | module |")
    assert text.endswith("<!-- end generated -->\nhand-written\n")
    assert regenerate(check=True, fast=True, root=root) == []


def test_unknown_block_and_unpaired_markers_are_errors_naming_the_line(tmp_path):
    root = _tree(tmp_path, "a\n\n<!-- generated: no-such-block -->\n<!-- end generated -->\n")
    with pytest.raises(BlockError, match=r"README.md:3: unknown generated block 'no-such-block'"):
        regenerate(check=True, fast=True, root=root)
    with pytest.raises(MarkerError, match=r"x.md:2: unpaired"):
        list(blocks("a\n<!-- generated: cli-modules -->\nno end\n", "x.md"))
    with pytest.raises(MarkerError, match=r"x.md:1: unpaired"):
        fill("<!-- end generated -->\n", lambda b: "", "x.md")


def test_fast_mode_leaves_result_blocks_alone(tmp_path):
    readme = "<!-- generated: paper-table -->\nwhatever\n<!-- end generated -->\n"
    root = _tree(tmp_path, readme)
    assert regenerate(check=True, fast=True, root=root) == []
    assert BLOCKS["paper-table"].runs_simulations and not BLOCKS["cli-modules"].runs_simulations


def test_command_line_check_exits_1_on_a_stale_block(tmp_path, monkeypatch, capsys):
    import docgen.__main__ as cli

    root = _tree(tmp_path, "<!-- generated: cli-modules -->\nold\n<!-- end generated -->\n")
    monkeypatch.setattr(cli, "ROOT", root)
    assert main(["--check", "--fast"]) == 1
    captured = capsys.readouterr()
    assert "README.md:1: block `cli-modules`" in captured.out and "run `python -m docgen`" in captured.err
