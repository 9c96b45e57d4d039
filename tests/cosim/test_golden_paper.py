"""Golden: the paper run gives the same metrics, time series, frames and events on every ECU link.

In process over our ``crd_inproc`` bus (the default), in process over
python-can's ``virtual`` bus (``--bus-interface virtual``), and out of process
in lock-step (``--ecu process``): the ECU sees the same frames at the same
cycle times, so everything but the wall time must be identical. The process
link runs for ``conservative`` only (the run with the most contingency
invocations; ``tests/cosim/test_ecu_process.py`` compares all three strategies
in and out of process), which keeps this test to a few seconds on 2 cores.
"""

from __future__ import annotations

import dataclasses

import pytest

from can_dbc import AUTHENTICATORS, LAYOUTS, generate_key, write_key_file
from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import run_scenario
from cosim.scenarios.loader import load_scenario

LINKS = {
    "crd_inproc": {},
    "virtual": {"interface": "virtual"},
    "process": {"mode": "process"},
}
#: what only the lock-step adds to the log: SimClock and its SecOC authenticator, and (issue 25) the
#: ECU process's announcement of what it runs, EcuIdentity and its authenticator
_CLOCK_IDS = {LAYOUTS["SimClock"].frame_id, AUTHENTICATORS["SimClock"],
              LAYOUTS["EcuIdentity"].frame_id, AUTHENTICATORS["EcuIdentity"]}


@pytest.fixture(scope="module")
def key_file(tmp_path_factory):
    """One SecOC key for every link, so that the authenticator frames agree too."""
    return str(write_key_file(tmp_path_factory.mktemp("key") / "run.key", generate_key()))


def _outcome(record) -> tuple:
    metrics = dataclasses.replace(record.metrics, wall_time_s=0.0)
    return metrics, record.rows, record.frames, record.events, record.error


@pytest.mark.slow
@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening"])
def test_paper_run_is_identical_over_every_link(plant_fmu3, strategy, key_file):
    sc = load_scenario(PAPER_SCENARIO)
    links = {name: EcuOptions(key_file=key_file, **kwargs) for name, kwargs in LINKS.items()}
    reference = _outcome(run_scenario(sc, plant_fmu3, strategy, ecu=links["crd_inproc"]))
    assert reference[0].sim_time_s > 13.0 and len(reference[1]) > 1300 and len(reference[2]) > 4000
    for name in ("virtual", "process") if strategy == "conservative" else ("virtual",):
        other = _outcome(run_scenario(sc, plant_fmu3, strategy, ecu=links[name]))
        assert other[0] == reference[0], name
        assert other[1] == reference[1], name
        # the lock-step adds one SimClock (and its authenticator) per cycle to the log, and the ECU
        # process its EcuIdentity each second; everything else matches frame for frame
        frames = [f for f in other[2] if f.arbitration_id not in _CLOCK_IDS] if name == "process" else other[2]
        assert frames == reference[2], name
        assert other[3:] == reference[3:], name
