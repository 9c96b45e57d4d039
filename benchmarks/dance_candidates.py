"""Why the dance shows in the paper's speed trace and not in ours: each candidate, by experiment.

Run: ``python benchmarks/dance_candidates.py``. For each variant of the paper
scenario (one change at a time, the same for all three strategies) it prints,
per strategy, the separate decelerations counted from the speed trace
(:mod:`cosim.results.speed_dance`), the dance's amplitude (mean recovery,
m/s), the ECU's contingency count and the outcome, then the paper's claims.

Candidates (issue 14):

* ``loop``: a ROS-style perception-to-actuation loop. Emulated by holding the
  gateway's actuation for N ECU cycles (a zero-order hold at 1/(N·10 ms)),
  on top of the radar latency; and by a longer radar latency.
* ``hold``: a contingency that, once invoked, holds until a release margin is
  restored (``contingency_release_ratio``) or until the car has (nearly)
  stopped (``contingency_release_speed_mps``), :mod:`ecu.core.step`.
* the stale range: ``ObjectTrack`` arrives every 50 ms (DBC) and the ECU holds
  the last range in between; sending it every 10 ms (and without latency)
  shows how much of the chatter that causes.
* ``fast``: faster actuators (the issue's measurement: brake dead time
  0.03 s, tau 0.05 s, throttle tau 0.05 s), faster in both directions; brakes
  that only release faster would need a plant change and are not tried.
* the driver re-applying throttle: the paper's driver already holds full
  throttle at every release (``full_throttle``), so there is nothing to add.
"""

from __future__ import annotations

import dataclasses
from types import MappingProxyType

import cosim.loop.master as master
from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.results.paper_claims import REQUIRED, evaluate
from cosim.results.speed_dance import speed_dance
from cosim.scenarios.loader import load_scenario
from cosim.world.gateway import Gateway


def held_gateway(n_cycles: int) -> type[Gateway]:
    """A gateway whose actuation changes only every ``n_cycles`` cycles (a slower control loop)."""

    class HeldGateway(Gateway):
        def __init__(self, *args, **kwargs) -> None:
            super().__init__(*args, **kwargs)
            self._k, self._held = 0, None

        def actuation(self, pedals, t_s):
            fresh = super().actuation(pedals, t_s)
            if self._k % n_cycles == 0 or self._held is None:
                self._held = fresh
            self._k += 1
            return self._held

    return HeldGateway


def every_cycle_tracks() -> None:
    """Send ``ObjectTrack`` every 10 ms instead of the DBC's 50 ms (an experiment on the stale range)."""
    original = master.ClosedLoop.__init__

    def init(self, *args, **kwargs):
        original(self, *args, **kwargs)
        self.n_track = 1

    master.ClosedLoop.__init__ = init
    return original


def variant(base, ecu=None, plant=None, radar_latency_s=None):
    sc = base
    if ecu:
        sc = dataclasses.replace(sc, ecu=dataclasses.replace(
            sc.ecu, parameters=MappingProxyType(dict(sc.ecu.parameters) | ecu)))
    if plant:
        sc = dataclasses.replace(sc, plant=dataclasses.replace(
            sc.plant, parameters=MappingProxyType(dict(sc.plant.parameters) | plant)))
    if radar_latency_s is not None:
        sc = dataclasses.replace(sc, radar=dataclasses.replace(sc.radar, latency_s=radar_latency_s))
    return sc


def report(name: str, sc, fmu, gateway_cls=Gateway) -> None:
    master.Gateway = gateway_cls
    try:
        recs = [master.run_scenario(sc, fmu, s) for s in REQUIRED]
    finally:
        master.Gateway = Gateway
    cells = []
    for r in recs:
        speeds = r.column("speed_mps")
        d = speed_dance(speeds)
        fine = speed_dance(speeds, FINE_MPS, FINE_MPS)
        m = r.metrics
        end = f"hit {m.impact_speed_mps:.1f} m/s" if m.collided else f"stops {m.final_gap_m:.1f} m short"
        cells.append(f"{d.decelerations} / {max(fine.rises_mps, default=0.0):.2f} / "
                     f"{m.contingency_invocations} / {end}")
    claims = "".join("P" if c.passed else "F" for c in evaluate(recs))
    print(f"| {name} | " + " | ".join(cells) + f" | {claims} |", flush=True)


#: a fine detector for the largest recovery, however small (m/s).
FINE_MPS = 0.05


def main() -> None:
    base = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(base)
    print("cells: decelerations in the speed trace (0.5 m/s detector) / largest speed recovery (m/s) /"
          " ECU contingency invocations / outcome\n")
    print("| variant | none | conservative | tightening | claims 1-5 |\n|---|---|---|---|---|")
    report("baseline", base, fmu)
    for lat in (0.2, 0.3):
        report(f"loop: radar latency {lat} s", variant(base, radar_latency_s=lat), fmu)
    for n in (5, 10):
        report(f"loop: actuation held {n * 10} ms", base, fmu, held_gateway(n))
    for key, values in (("brake_dead_time", (0.05, 0.2)), ("brake_time_constant", (0.06, 0.2)),
                        ("throttle_time_constant", (0.1, 0.5))):
        for value in values:
            report(f"plant {key} {value}", variant(base, plant={key: value}), fmu)
    fast = {"brake_dead_time": 0.03, "brake_time_constant": 0.05, "throttle_time_constant": 0.05}
    report("fast actuators (issue 14)", variant(base, plant=fast), fmu)
    no_lag = {"brake_dead_time": 0.0, "brake_time_constant": 0.02, "throttle_time_constant": 0.05}
    for n in (1, 10):
        report(f"lag-free plant, actuation held {n * 10} ms", variant(base, plant=no_lag), fmu, held_gateway(n))
    for ratio in (1.2, 1.5):
        report(f"hold: release ratio {ratio}", variant(base, ecu={"contingency_release_ratio": ratio}), fmu)
    report("hold: to standstill (release <= 0.1 m/s)",
           variant(base, ecu={"contingency_release_speed_mps": 0.1}), fmu)
    original = every_cycle_tracks()
    try:
        report("stale range removed: ObjectTrack every 10 ms", base, fmu)
        report("... and radar latency 0", variant(base, radar_latency_s=0.0), fmu)
    finally:
        master.ClosedLoop.__init__ = original


if __name__ == "__main__":
    main()
