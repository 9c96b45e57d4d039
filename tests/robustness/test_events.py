"""Rate-limited, summarised events (cosim.results.events) and ``[checks] expect_events``."""

from __future__ import annotations

import pytest

from cosim.errors import ConfigError
from cosim.results.events import (EXIT_FAULT_EVENT, KEEP_EVERY_S, KEEP_FIRST, SUPPRESSED, EventLog, fault_exit,
                                  merge_events, unexpected_faults)
from cosim.results.run_record import RunEvent, RunMetrics, RunRecord
from cosim.scenarios.loader import scenario_from_dict


def test_the_first_events_of_a_kind_are_kept_then_one_per_interval():
    log = EventLog()
    kept = [log.add(RunEvent(i * 0.01, "bus_error", "peer gone")) for i in range(114_074)]  # 1140 s of frames
    assert kept[:KEEP_FIRST] == [True] * KEEP_FIRST
    assert log.counts == {"bus_error": 114_074}
    assert len(log) == KEEP_FIRST + int(1140 // KEEP_EVERY_S)  # 10, then one per 10 s of simulated time
    (summary,) = log.summaries()
    assert summary.kind == SUPPRESSED and summary.detail.startswith("bus_error: 114074 in all from t = 0.000 s")


def test_kinds_are_limited_separately_and_rare_events_always_kept():
    log = EventLog([RunEvent(0.001 * i, "bus_error", "x") for i in range(100)])
    assert log.add(RunEvent(0.2, "ecu_lost", "gone"))
    assert [e.kind for e in log].count("bus_error") == KEEP_FIRST


def test_merge_keeps_the_counts_of_a_limited_source_and_sorts_by_time():
    link = EventLog([RunEvent(2.0 + 0.01 * i, "bus_error", "x") for i in range(50)])
    merged = merge_events(link, [RunEvent(1.0, "override_timeout", "y")], [RunEvent(3.0, "collision", "z")])
    assert merged.counts["bus_error"] == 50
    assert [e.t_s for e in merged] == sorted(e.t_s for e in merged)
    summaries = [e for e in merged if e.kind == SUPPRESSED]
    assert len(summaries) == 1 and summaries[0].detail.startswith("bus_error: 50 in all")
    assert {"override_timeout", "collision"} <= {e.kind for e in merged}


def test_fault_events_make_exit_4_unless_expected():
    record = RunRecord("tightening", RunMetrics("tightening"), events=[RunEvent(2.0, "ecu_lost", "exited")])
    assert fault_exit([record]) == EXIT_FAULT_EVENT == 4
    assert unexpected_faults([record]) == ["tightening: t=2.000 s ecu_lost: exited"]
    assert fault_exit([record], expected=["ecu_lost"]) == 0
    record.events.append(RunEvent(2.5, "second_ecu", "two senders"))
    assert fault_exit([record], expected=["ecu_lost"]) == 4
    assert fault_exit([RunRecord("none", RunMetrics("none"), events=[RunEvent(1.0, "collision", "")])]) == 0


def test_expect_events_is_checked_at_load():
    sc = scenario_from_dict({"checks": {"expect_events": ["ecu_lost", "second_ecu"]}})
    assert sc.checks.expect_events == ("ecu_lost", "second_ecu")
    with pytest.raises(ConfigError, match=r"checks.expect_events: .*got 'ecu_lsot'; did you mean 'ecu_lost'\?$"):
        scenario_from_dict({"checks": {"expect_events": ["ecu_lsot"]}})
    with pytest.raises(ConfigError, match="checks.expect_events: expected a list of event names"):
        scenario_from_dict({"checks": {"expect_events": "ecu_lost"}})


def test_an_event_log_pickles_with_its_counts():
    """Records travel back from Dask workers (crd matrix) pickled; the counts must survive."""
    import pickle

    log = EventLog([RunEvent(0.01 * i, "bus_error", "x") for i in range(30)])
    back = pickle.loads(pickle.dumps(log))
    assert isinstance(back, EventLog) and list(back) == list(log) and back.counts == {"bus_error": 30}
    assert back.summaries() == log.summaries()
