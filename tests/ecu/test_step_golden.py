"""The ECU core reproduces, bit for bit, every state and output of the recorded core.

``data/step_golden.npz`` holds what the core of ``d2cf42d`` (its step written
out by hand, issue 10), re-recorded for issue 25 twice: wheelspin is driving (the
state carries the driven wheels' lead and the cycles since the accelerator; 14 of
the 38,400 cycles decided otherwise), and track confirmation (with
``track_confirm_reports`` 1 every cycle decided as before, with the default 3,
837 did not); and for issue 22 (behind a moving object that closes in, our stopping path must
also stay clear of the object's own stopping region, :mod:`ecu.core.relative_stop`, when the object
moves faster than 1.0 m/s: each drive that differs does so first at a cycle where the object moves and
closes, at the ECU's speed estimate or at the true speed :func:`ecu.core.plan_cycle` is called with;
the paper run and every standing-target cell of the 1-D catalogues are unchanged); and for issue 23 (the
state carries ``slow_cycles``, :mod:`ecu.core.way_out`, 0 in every drive here: all 38,400 cycles decide as
before, compared before re-recording), and again for issue 23 (the state carries ``way_out_backoffs``, 0 in
every drive here: all 38,400 cycles decide as before, compared before re-recording), and again for issue 22
(the state carries ``steer_evasion``, the held lane change, :mod:`ecu.core.lane_change_tracking`, empty in every
drive here: all 38,400 cycles decide as before, compared before re-recording); returned over the
seeded drives of :mod:`.drives`:
every strategy, four input-noise rates (forged, timed-out, future-stamped,
E2E-invalid, receiver-flagged and non-finite inputs among them) and four
parameter variants, 600 cycles each. Per cycle it keeps an 8-byte digest of
the exact text of the next state, the outputs and :func:`ecu.core.plan_cycle`
(floats by ``repr``, so -0.0 and NaN count; every value with its type), and
the outputs' decisions in full. The core composed from its one-concern modules
(issue 20) must give the same digest at every cycle. Regenerate only for a
deliberate change of behaviour: ``python -m tests.ecu.test_step_golden
--write`` records the core as it is. ~3 s.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pytest

from ecu.core import Mode, plan_cycle, step

from .drives import DECISIONS, NOISES, STRATEGIES, drive, key, record_drive

GOLDEN = Path(__file__).with_name("data") / "step_golden.npz"


def _golden() -> dict[str, np.ndarray]:
    with np.load(GOLDEN) as data:
        return {name: data[name] for name in data.files}


def _inputs_at(strategy: str, noise: float, cycle: int) -> tuple:
    """(params, inputs) of the drive's ``cycle``-th cycle overall, to name a differing cycle."""
    for n, (params, _k, _speed, inputs) in enumerate(drive(strategy, noise)):
        if n == cycle:
            return params, inputs
    raise IndexError(cycle)


@pytest.mark.parametrize("noise", NOISES)
@pytest.mark.parametrize("strategy", STRATEGIES)
def test_core_reproduces_the_golden_drive(strategy: str, noise: float) -> None:
    golden = _golden()
    digests, decisions = record_drive(strategy, noise, step, plan_cycle)
    expected, expected_decisions = golden[f"{key(strategy, noise)}/digests"], golden[f"{key(strategy, noise)}/decisions"]
    assert digests.shape == expected.shape
    differ = np.flatnonzero(digests != expected)
    if differ.size:
        cycle = int(differ[0])
        decided = dict(zip(DECISIONS, expected_decisions[cycle].tolist()))
        now = dict(zip(DECISIONS, decisions[cycle].tolist()))
        pytest.fail(f"{differ.size} cycles differ, the first {cycle}: decisions then {decided}, now {now}; "
                    f"(params, inputs) {_inputs_at(strategy, noise, cycle)}")


def test_the_golden_drives_reach_every_mode() -> None:
    """The recorded drives exercise the planner (not only FAULT), the faults and the degraded braking."""
    golden = _golden()
    mode, flags, decel = (DECISIONS.index(name) for name in ("mode", "fault_flags", "brake_decel_request_mps2"))
    for strategy in STRATEGIES:
        modes = set(golden[f"{key(strategy, 0.0)}/decisions"][:, mode].astype(int))
        assert {Mode.STANDBY, Mode.CONTINGENCY, Mode.FAULT} <= modes
        assert (Mode.TIGHTENING in modes) == (strategy in ("tightening", "adaptive"))
    every = np.concatenate([golden[n] for n in golden if n.endswith("/decisions")])
    faulted = every[:, mode] == Mode.FAULT
    assert (every[faulted, flags] != 0).any() and (every[faulted, decel] > 0).any()  # held or degraded braking
    assert len(set(golden[n].tobytes() for n in golden if n.endswith("/digests"))) == len(STRATEGIES) * len(NOISES)


def write() -> None:
    """Record the core as it is now into :data:`GOLDEN`."""
    arrays = {}
    for strategy in STRATEGIES:
        for noise in NOISES:
            digests, decisions = record_drive(strategy, noise, step, plan_cycle)
            arrays[f"{key(strategy, noise)}/digests"] = digests
            arrays[f"{key(strategy, noise)}/decisions"] = decisions.T.copy().T  # column-major compresses better
    np.savez_compressed(GOLDEN, **arrays)
    print(f"{GOLDEN}: {GOLDEN.stat().st_size} bytes")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="record the current core into the golden file")
    if parser.parse_args().write:
        write()
