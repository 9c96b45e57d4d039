"""Imports go one way: can_dbc <- ecu <- cosim; fmu_plant and can_transport stand alone."""

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OURS = {"can_dbc", "ecu", "cosim", "fmu_plant", "can_transport"}
ALLOWED = {
    "can_dbc": set(),
    "ecu": {"can_dbc"},
    "cosim": {"can_dbc", "ecu", "fmu_plant", "can_transport"},
    "fmu_plant": set(),
    "can_transport": set(),
}


def _imported_packages(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(), filename=str(path))
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
    return found & OURS


@pytest.mark.parametrize("package", sorted(ALLOWED))
def test_import_direction(package):
    files = sorted((ROOT / package).rglob("*.py"))
    assert files, f"package {package} has no modules"
    violations = []
    for path in files:
        bad = _imported_packages(path) - ALLOWED[package] - {package}
        if bad:
            violations.append(f"{path.relative_to(ROOT)} imports {sorted(bad)}")
    assert not violations, "\n".join(violations)


def test_checker_sees_a_violation(tmp_path):
    sample = tmp_path / "x.py"
    sample.write_text("from cosim.loop.master import run\nimport ecu.core\n")
    assert _imported_packages(sample) == {"cosim", "ecu"}
