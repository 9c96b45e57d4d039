"""Fixtures: every HIL test runs once per backend (``lockstep``, ``realtime``, ``process``).

A new backend is one more entry in ``harness.BACKENDS`` and in ``MODES``;
the tests do not change. ``process`` runs ``crd ecu`` as a separate OS
process over the ``crd_unix`` transport. The wall-clock backends carry the
``wallclock`` marker (``pytest -m "not wallclock"`` leaves them out; CI runs them).
"""

from __future__ import annotations

import uuid

import pytest

from ecu import EcuConfig

from . import harness

MODES = ("lockstep", "realtime", "process")
#: the backends that run on the wall clock: marked ``wallclock`` (deadlines get the backend's slack)
WALLCLOCK = ("realtime", "process")


@pytest.fixture(params=[pytest.param(m, marks=pytest.mark.wallclock) if m in WALLCLOCK else m for m in MODES])
def mode(request) -> str:
    return request.param


@pytest.fixture
def start_ecu(mode):
    """``start_ecu(**config) -> Harness`` around a fresh ECU on a unique virtual channel."""
    started: list[harness.Harness] = []

    def start(**config) -> harness.Harness:
        channel = f"hil-{mode}-{uuid.uuid4().hex[:12]}"
        h = harness.start(mode, EcuConfig(**config), channel)
        started.append(h)
        return h

    yield start
    for h in started:
        h.close()
