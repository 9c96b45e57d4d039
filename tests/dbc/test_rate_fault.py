"""``RateMonitor.fault`` is written out for speed; it must stay ``too_fast or too_slow`` exactly."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from can_dbc.rate import RateMonitor

# arrivals as gaps in whole 10 ms cycles (0: a second frame in the same cycle; 6+: a silence)
GAPS = st.lists(st.integers(min_value=0, max_value=12), min_size=1, max_size=120)


@settings(max_examples=300, deadline=None)
@given(gaps=GAPS, ask_after=st.integers(min_value=0, max_value=12))
def test_fault_is_too_fast_or_too_slow(gaps, ask_after):
    rate = RateMonitor(0.01)
    k = 0
    for gap in gaps:
        k += gap
        t_s = k * 0.01
        rate.arrive(t_s)
        for probe in (t_s, (k + ask_after) * 0.01):
            assert rate.fault(probe) == (rate.too_fast(probe) or rate.too_slow(probe))
