"""The README's quick start and CI agree: .ci/run runs the README's test command."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _quick_start_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    block = re.search(r"## Quick start.*?```(?:sh|bash)?\n(.*?)```", text, re.S)
    assert block, "README has no Quick start code block"
    return [line for line in block.group(1).splitlines() if line.strip() and not line.startswith("#")]


def test_quick_start_is_exactly_two_commands():
    commands = _quick_start_commands()
    assert len(commands) == 2, commands
    assert "pytest" in commands[1] and "[test]" in commands[1]


def test_ci_runs_the_readme_test_command():
    test_command = _quick_start_commands()[1]
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    assert test_command in ci_lines


def test_readme_is_short_and_states_its_limits_before_the_quick_start():
    text = (ROOT / "README.md").read_text()
    assert len(text.splitlines()) <= 200
    assert text.index("## Limits") < text.index("## Quick start")


def test_ci_builds_the_documentation_site_strictly_after_the_tests():
    ci_lines = (ROOT / ".ci" / "run").read_text().splitlines()
    build = next(i for i, line in enumerate(ci_lines) if "mkdocs build --strict" in line)
    assert build > ci_lines.index(_quick_start_commands()[1])
    assert "strict: true" in (ROOT / "mkdocs.yml").read_text()
