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

from cosim.cli.paper import PAPER_SCENARIO
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import run_scenario
from cosim.scenarios.loader import load_scenario

LINKS = {
    "crd_inproc": EcuOptions(),
    "virtual": EcuOptions(interface="virtual"),
    "process": EcuOptions(mode="process"),
}


def _outcome(record) -> tuple:
    metrics = dataclasses.replace(record.metrics, wall_time_s=0.0)
    return metrics, record.rows, record.frames, record.events, record.error


@pytest.mark.slow
@pytest.mark.parametrize("strategy", ["none", "conservative", "tightening"])
def test_paper_run_is_identical_over_every_link(plant_fmu3, strategy):
    sc = load_scenario(PAPER_SCENARIO)
    reference = _outcome(run_scenario(sc, plant_fmu3, strategy, ecu=LINKS["crd_inproc"]))
    assert reference[0].sim_time_s > 13.0 and len(reference[1]) > 1300 and len(reference[2]) > 4000
    for name in ("virtual", "process") if strategy == "conservative" else ("virtual",):
        other = _outcome(run_scenario(sc, plant_fmu3, strategy, ecu=LINKS[name]))
        assert other[0] == reference[0], name
        assert other[1] == reference[1], name
        # the lock-step adds one SimClock per cycle to the log; everything else matches frame for frame
        frames = [f for f in other[2] if f.arbitration_id != 0x7F0] if name == "process" else other[2]
        assert frames == reference[2], name
        assert other[3:] == reference[3:], name
