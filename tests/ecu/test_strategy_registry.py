"""Strategies are a registry that agrees with the DBC, and a new one is its module plus a VAL_ line.

The registry (:data:`ecu.core.strategies.REGISTRY`) must name exactly the
``EcuStatus.Strategy`` values of the DBC, read here by cantools on its own.
The toy test copies crd's packages into a temporary directory, adds one
module and one value to the DBC's ``VAL_`` line there, and runs a real
closed loop (``crd run --strategy toy``) from that tree in a subprocess: the
command line, the configuration, the core and ``EcuStatus`` must all take
the new strategy with no other edit. A module without its ``VAL_`` entry,
or an entry without its module, must stop the import with a message naming
it. ~10 s.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import cantools
import pytest

import ecu
from can_dbc import DBC_PATH
from ecu import EcuConfig
from ecu.core import CoreParams
from ecu.core.strategies import REGISTRY
from ecu.core.strategy import NO_TIGHTENING, Strategy

ROOT = Path(ecu.__file__).resolve().parents[1]
PACKAGES = ("can_dbc", "ecu", "cosim", "fmu_plant", "can_transport")
DBC = cantools.database.load_file(str(DBC_PATH))
TOY = '''"""``toy``: a test strategy, 0.7 of the peak deceleration, no tightening."""

from ..strategy import FixedDeceleration


class Toy(FixedDeceleration):
    def decel_fraction(self, params):
        return 0.7


STRATEGY = Toy()
'''
SCENARIO = '[scenario]\nduration_s = 6.0\n[object]\nposition_m = 60.0\n[ecu]\nstrategy = "none"\n'
#: run in the copied tree after ``crd run``: what the run's CAN log and the loaders say of ``toy``
CHECK = '''
import json, sys
import can
from can_dbc import Receiver, STRATEGY_CODES
from ecu import EcuConfig
from ecu.core import CoreParams
status = Receiver(["EcuStatus"])
codes = {f.signals["Strategy"] for m in can.LogReader(sys.argv[1]) if (f := status.receive(m)) is not None}
print(json.dumps({"codes": sorted(codes), "dbc": STRATEGY_CODES["toy"],
                  "decel": CoreParams(strategy="toy").model_decel_mps2, "config": EcuConfig(strategy="toy").strategy}))
'''


def _dbc_strategies() -> dict[str, int]:
    signal = DBC.get_message_by_name("EcuStatus").get_signal_by_name("Strategy")
    return {str(name).lower(): int(value) for value, name in signal.choices.items()}


def test_the_registry_is_the_dbcs_strategy_enumeration():
    assert list(REGISTRY) == sorted(_dbc_strategies(), key=_dbc_strategies().get)
    for name, rules in REGISTRY.items():
        assert isinstance(rules, Strategy)
        params = CoreParams(strategy=name)
        assert params.strategy_rules is rules and params.strategy_code == _dbc_strategies()[name]
        assert params.model_decel_mps2 == rules.decel_fraction(params) * params.peak_decel_mps2


def test_what_each_paper_strategy_decides():
    p = {name: CoreParams(strategy=name) for name in REGISTRY}
    assert {name: q.model_decel_mps2 for name, q in p.items()} == pytest.approx(
        {"none": 8.1, "conservative": 7.2, "tightening": 8.1, "adaptive": 8.1})
    assert [name for name, q in p.items() if q.strategy_rules.tighten(0.5, q) is not NO_TIGHTENING] \
        == ["tightening", "adaptive"]


def test_an_unknown_strategy_is_refused():
    with pytest.raises(ValueError, match=r"strategy: expected one of \['none', 'conservative', 'tightening', "
                                         r"'adaptive'\], got 'fast'"):
        CoreParams(strategy="fast")


@pytest.fixture
def tree(tmp_path: Path) -> Path:
    """A copy of crd's packages (with the built plant FMU's cache, if any) to edit."""
    for name in PACKAGES:
        shutil.copytree(ROOT / name, tmp_path / name, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return tmp_path


def _add_val(tree: Path, entry: str) -> None:
    dbc = tree / "can_dbc" / "active_safety.dbc"
    old = 'VAL_ 928 Strategy 0 "NONE" 1 "CONSERVATIVE" 2 "TIGHTENING" 3 "ADAPTIVE" ;'
    text = dbc.read_text()
    assert text.count(old) == 1
    dbc.write_text(text.replace(old, old[:-1] + entry + " ;"))


def _python(tree: Path, *args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    return subprocess.run([sys.executable, *args], cwd=cwd or tree, env=env, capture_output=True, text=True,
                          timeout=300)


def test_a_toy_strategy_is_its_module_and_one_val_entry(tree: Path):
    (tree / "ecu" / "core" / "strategies" / "toy.py").write_text(TOY)
    _add_val(tree, '4 "TOY"')
    (tree / "toy.toml").write_text(SCENARIO)
    run = _python(tree, "-m", "cosim.cli.main", "run", "toy.toml", "--strategy", "toy", "--out", "out")
    assert run.returncode == 0, run.stderr[-3000:]
    assert "toy" in run.stdout
    check = _python(tree, "-c", CHECK, str(tree / "out" / "toy" / "can.blf"))
    assert check.returncode == 0, check.stderr[-3000:]
    assert json.loads(check.stdout) == {"codes": [4], "dbc": 4, "decel": pytest.approx(0.7 * 9.0), "config": "toy"}
    assert "toy" not in REGISTRY and "toy" not in EcuConfig.__dataclass_fields__  # this process: untouched


def test_a_module_without_its_val_entry_stops_the_import(tree: Path):
    (tree / "ecu" / "core" / "strategies" / "toy.py").write_text(TOY)
    done = _python(tree, "-c", "import ecu.core")
    assert done.returncode != 0
    assert "expected a VAL_ entry of EcuStatus.Strategy" in done.stderr and "['toy']" in done.stderr


def test_a_val_entry_without_its_module_stops_the_import(tree: Path):
    _add_val(tree, '4 "TOY"')
    done = _python(tree, "-c", "import ecu.core")
    assert done.returncode != 0
    assert "expected a module in ecu/core/strategies" in done.stderr and "4 'TOY'" in done.stderr
