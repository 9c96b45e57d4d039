"""Fixtures: every HIL test runs once per backend (``lockstep``, ``realtime``, ``process``).

A new backend is one more entry in ``harness.BACKENDS`` and in ``MODES``;
the tests do not change. ``process`` runs ``crd ecu`` as a separate OS
process over the ``crd_unix`` transport.
"""

from __future__ import annotations

import uuid

import pytest

from ecu import EcuConfig

from . import harness

MODES = ("lockstep", "realtime", "process")


@pytest.fixture(params=MODES)
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
