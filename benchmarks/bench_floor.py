"""The per-cycle floor of the in-process loop with SecOC on: the work no Python design can skip.

Run: ``python benchmarks/bench_floor.py [--strategy conservative] [--repeat 31]``.

This benchmark runs the paper scenario once in process (SecOC on, as issue 15 requires), counts
what one 10 ms ECU cycle must exchange, and times each piece of that work alone, in this process,
with the project's own functions, the ones the loop runs:

* the FMU: fmpy's raw ctypes calls, as bound by :class:`cosim.world.plant_fmu.FmuPlant`
  (set the inputs, one ``doStep`` over the 10 ms cycle, get the outputs), without any Python
  around them;
* every SecOC MAC: each authenticator frame is signed once and verified once, each the truncated
  CMAC-AES-128 over 18 bytes of :mod:`can_dbc.secoc` (``_Mac.mac``);
* every frame as a ``can.Message`` (the ECU's bus is a ``can.BusABC``), built positionally;
* every E2E CRC-8: computed by the sender and again by the receiver of each protected frame
  (:func:`can_dbc.crc.e2e_p01_crc8`).

Their sum is the floor. For context, and not part of it: the ECU core's step over the inputs
recorded from the same run, the packing and unpacking of the signals through the codec's
tables, and the measured closed loop (CPU time, the same process): the loop's cost beyond the
floor is the Python around that work. The figures are medians over ``--repeat`` batches; the
machine may be shared, so the load average is printed. (The leanest hand-written form of the
whole cycle that issue 10 kept beside this, a copy of the codec, CRC, rate and SecOC code, is
gone with the 300x goal it served: issue 20.)
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections import Counter

import can

import ecu.node as ecu_node
from can_dbc import AUTHENTICATORS, ECU_CYCLE_S, LAYOUTS_BY_ID, SecOcSender, encode, generate_key
from can_dbc.codec import _payload
from can_dbc.crc import e2e_p01_crc8
from can_dbc.receiver import _decode
from cosim.cli.paper import PAPER_SCENARIO
from cosim.loop.experiment import resolve_fmu
from cosim.loop.master import ClosedLoop
from cosim.scenarios.loader import load_scenario
from cosim.world.plant_fmu import FmuPlant

BATCH = 200


def median_us(fn, repeat: int, batch: int = BATCH) -> float:
    """Median over ``repeat`` batches of the time (µs) of one call of ``fn``."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(batch):
            fn()
        times.append((time.perf_counter() - t0) / batch * 1e6)
    return statistics.median(times)


def recorded_run(sc, fmu, strategy: str) -> tuple[object, list, float]:
    """One in-process paper run: its record, the core's (state, inputs, params) per cycle, CPU µs/cycle."""
    calls, real_step = [], ecu_node.core_step

    def spy(state, inputs, params):
        calls.append((state, inputs, params))
        return real_step(state, inputs, params)

    loop = ClosedLoop(sc, fmu, strategy)  # built before the spy: the warm-up below is not recorded
    ecu_node.core_step = spy
    try:
        c0 = time.process_time()
        record = loop.run()
        cpu_s = time.process_time() - c0
    finally:
        ecu_node.core_step = real_step
    return record, calls, cpu_s / len(calls) * 1e6


def fmu_cycle_us(sc, fmu, repeat: int) -> float:
    """Raw set + doStep(one ECU cycle) + get of the plant FMU (µs), no Python wrapper around them."""
    plant = FmuPlant(sc.plant, fmu)
    try:
        set_, set_args = plant._set, plant._set_in  # noqa: SLF001 - the raw calls are what is measured
        get, get_args = plant._get, plant._get_out  # noqa: SLF001
        step, comp, tail = plant._raw_step, plant._component, plant._step_tail  # noqa: SLF001
        k = [0]

        def cycle() -> None:
            set_(*set_args)
            step(comp, k[0] * ECU_CYCLE_S, ECU_CYCLE_S, *tail)
            get(*get_args)
            k[0] += 1
        return median_us(cycle, repeat, batch=50)
    finally:
        plant.close()


def per_cycle_counts(record) -> dict[str, float]:
    """Frames per ECU cycle of the run, split into protected (E2E) and authenticator frames."""
    cycles = len(record.rows)
    by_id = Counter(f.arbitration_id for f in record.frames)
    auth_ids = set(AUTHENTICATORS.values())
    protected = sum(n for fid, n in by_id.items() if fid in LAYOUTS_BY_ID)
    auth = sum(n for fid, n in by_id.items() if fid in auth_ids)
    return {"frames": len(record.frames) / cycles, "protected": protected / cycles, "auth": auth / cycles}


def floor_items(sc, fmu, counts: dict[str, float], repeat: int) -> list[tuple[str, float, float]]:
    """(what, count per cycle, µs each) of the irreducible work."""
    mac, frame = SecOcSender(generate_key()).mac, bytes(range(8))
    data = bytearray(range(8))
    return [
        ("FMU: set + doStep(10 ms) + get, raw fmpy calls", 1.0, fmu_cycle_us(sc, fmu, repeat)),
        ("SecOC MAC (can_dbc.secoc): sign + verify", 2 * counts["auth"], median_us(lambda: mac(0xA0, frame, 7), repeat)),
        ("can.Message construction, every frame", counts["frames"],
         median_us(lambda: can.Message(0.0, 0x90, False, False, False, None, 8, data), repeat)),
        ("E2E CRC-8: sender + receiver", 2 * counts["protected"], median_us(lambda: e2e_p01_crc8(0x5A, data), repeat)),
    ]


def context_items(record, calls: list, repeat: int) -> list[tuple[str, float, float]]:
    """(what, count per cycle, µs each) of work the loop does beyond the floor."""
    cycles = len(record.rows)
    n = min(len(calls), 4000)

    def core_steps() -> None:
        for state, inputs, params in calls[:n]:
            ecu_node.core_step(state, inputs, params)
    core_us = median_us(core_steps, max(3, repeat // 5), batch=1) / n
    layout = LAYOUTS_BY_ID[0xA0]  # WheelSpeeds: sent every cycle, four signals
    signals = {s.name: 50.0 for s in layout.signals}
    payload = int.from_bytes(encode(layout.name, signals, 0).data, "little")
    protected = sum(1 for f in record.frames if f.arbitration_id in LAYOUTS_BY_ID) / cycles
    return [
        ("ECU core step (recorded inputs)", 1.0, core_us),
        ("signal packing, WheelSpeeds (codec tables)", protected, median_us(lambda: _payload(layout, signals, 3), repeat)),
        ("signal unpacking, WheelSpeeds (codec tables)", protected, median_us(lambda: _decode(layout, payload), repeat)),
    ]


def report(strategy: str, counts: dict, floor: list, context: list, loop_us: float) -> None:
    print(f"paper run, {strategy}, in process, SecOC on; load average "
          f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}")
    print(f"per 10 ms cycle: {counts['frames']:.2f} frames ({counts['protected']:.2f} protected, "
          f"{counts['auth']:.2f} authenticators)")
    print(f"{'item':<52}{'per cycle':>10}{'µs each':>10}{'µs/cycle':>10}")
    for title, rows in (("floor", floor), ("beyond the floor (context)", context)):
        for what, count, each in rows:
            print(f"{what:<52}{count:>10.2f}{each:>10.2f}{count * each:>10.1f}")
        total = sum(c * e for _, c, e in rows)
        print(f"{'  sum, ' + title:<72}{total:>10.1f}")
    floor_us = sum(c * e for _, c, e in floor)
    print(f"floor {floor_us:.1f} µs per cycle: at most {ECU_CYCLE_S * 1e6 / floor_us:.0f}x real time for this work "
          f"alone")
    print(f"floor + context {floor_us + sum(c * e for _, c, e in context):.1f} µs; the closed loop measured "
          f"{loop_us:.1f} µs per cycle of CPU time ({ECU_CYCLE_S * 1e6 / loop_us:.0f}x)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--strategy", default="conservative")
    parser.add_argument("--repeat", type=int, default=31, help="batches per item; medians are reported")
    args = parser.parse_args()
    sc = load_scenario(PAPER_SCENARIO)
    fmu = resolve_fmu(sc)
    recorded_run(sc, fmu, "none")  # warm up: imports, the FMU's first load
    record, calls, loop_us = recorded_run(sc, fmu, args.strategy)
    counts = per_cycle_counts(record)
    report(args.strategy, counts, floor_items(sc, fmu, counts, args.repeat), context_items(record, calls, args.repeat),
           loop_us)


if __name__ == "__main__":
    main()
