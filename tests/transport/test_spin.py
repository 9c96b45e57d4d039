"""``AdaptiveSpin``: poll only on a machine with a free core, and only while answers come soon."""

from __future__ import annotations

from pathlib import Path

from can_transport.spin import SAMPLE_PERIOD_S, AdaptiveSpin, usable_cpus


def _loadavg(tmp_path: Path, runnable: int) -> str:
    path = tmp_path / "loadavg"
    path.write_text(f"0.50 0.40 0.30 {runnable}/200 12345\n")
    return str(path)


def _sampled(spin: AdaptiveSpin, samples: int = 2) -> float:
    """The budget after ``samples`` samples of the load file (times are given, not read)."""
    budget = 0.0
    for k in range(samples):
        budget = spin.budget_s(1.0 + k * SAMPLE_PERIOD_S)
    return budget


def test_a_quiet_machine_and_short_waits_give_a_short_poll(tmp_path) -> None:
    spin = AdaptiveSpin(0.0005, _loadavg(tmp_path, usable_cpus()))
    for _ in range(40):
        spin.waited(0.0001)  # answers within 100 µs
    budget = _sampled(spin)
    assert spin.machine_quiet and 0.00015 < budget <= 0.0005


def test_more_runnable_tasks_than_cores_means_no_polling(tmp_path) -> None:
    spin = AdaptiveSpin(0.0005, _loadavg(tmp_path, usable_cpus() + 2))
    for _ in range(40):
        spin.waited(0.0001)
    assert _sampled(spin) == 0.0 and not spin.machine_quiet


def test_one_busy_sample_stops_polling(tmp_path) -> None:
    path = _loadavg(tmp_path, 1)
    spin = AdaptiveSpin(0.0005, path)
    for _ in range(40):
        spin.waited(0.0001)
    assert _sampled(spin) > 0.0
    Path(path).write_text(f"0.5 0.4 0.3 {usable_cpus() + 1}/200 1\n")
    assert spin.budget_s(2.0) == 0.0


def test_slow_answers_stop_polling_and_fast_ones_bring_it_back(tmp_path) -> None:
    spin = AdaptiveSpin(0.0005, _loadavg(tmp_path, 1))
    for _ in range(40):
        spin.waited(0.05)  # an idle peer: every wait times out after 50 ms
    assert _sampled(spin) == 0.0
    for _ in range(40):
        spin.waited(0.0001)
    assert _sampled(spin) > 0.0


def test_zero_or_no_load_file_never_polls(tmp_path) -> None:
    assert _sampled(AdaptiveSpin(0.0, _loadavg(tmp_path, 1))) == 0.0
    assert _sampled(AdaptiveSpin(0.0005, str(tmp_path / "absent"))) == 0.0
