"""An attacker on the in-process co-simulation bus (issue 15, findings 1-4).

:func:`attacked_run` runs the paper scenario in process and lets an attack
inject frames each cycle: ``to_ecu(t_s, cycle)`` frames reach the ECU before
the cycle's genuine frames; ``to_gateway(t_s, cycle, genuine)`` frames reach
the ECU *and* the gateway right after the ECU's own frames of the cycle.
The attacker knows the contract (valid CRCs and counters) but not the key.

The helpers work against the code before issue 15 too (options it lacks are
dropped), so each attack test can be shown to fail there.
"""

from __future__ import annotations

import dataclasses
from typing import Callable

import can

from can_dbc import CounterSequence, encode
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import ClosedLoop
from cosim.scenarios.loader import load_scenario

PAPER = "cosim/scenarios/paper_cyclist.toml"
KMH_PER_MPS = 3.6


def options(**wanted) -> EcuOptions:
    """``EcuOptions`` with the fields this version of the code has."""
    known = {f.name for f in dataclasses.fields(EcuOptions)}
    return EcuOptions(**{k: v for k, v in wanted.items() if k in known})


def attacked_run(fmu, strategy: str, authenticate: bool,
                 to_ecu: Callable[[float, int], list] = lambda t, k: [],
                 to_gateway: Callable[[float, int, list], list] = lambda t, k, g: [],
                 watch: Callable[[float, object], None] | None = None):
    """Run the paper scenario under attack; returns the run record (and calls ``watch(t, outputs)``)."""
    loop = ClosedLoop(load_scenario(PAPER), fmu, strategy, ecu=options(authenticate=authenticate))
    link = loop.link
    send, collect = link.send, link.collect

    def attacked_send(t_s, cycle, frames, *rest):  # (*rest: the older link API's cost argument)
        for msg in to_ecu(t_s, cycle):
            link._bus.send(msg)
        extra = send(t_s, cycle, frames, *rest)
        if watch is not None:
            watch(t_s, link.node.outputs)
        return extra

    def attacked_collect(t_s, cycle, *rest):
        genuine = collect(t_s, cycle, *rest)
        forged = to_gateway(t_s, cycle, genuine)
        for msg in forged:
            link._bus.send(msg)  # the ECU sees them on its bus next cycle
        return genuine + forged

    link.send, link.collect = attacked_send, attacked_collect
    return loop.run()


def wheel_frames(speed_mps: float, counters: CounterSequence, n: int) -> list[can.Message]:
    """``n`` E2E-valid WheelSpeeds frames (all four wheels at ``speed_mps``), counters in sequence."""
    kmh = speed_mps * KMH_PER_MPS
    return [encode("WheelSpeeds", {f"WheelSpeed{w}": kmh for w in ("FL", "FR", "RL", "RR")}, counters.next())
            for _ in range(n)]
