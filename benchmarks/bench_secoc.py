"""Receive with all issue-15 checks, with and without SecOC (median per frame, side by side).

Run: ``python benchmarks/bench_secoc.py [--messages N]``. Goal (issue 15): receive with all
checks and the MAC <= 20 µs per frame, median. Three receivers get the same genuine
WheelSpeeds/DriverInput/ObjectTrack stream at the DBC's rates, stamped with cycle times:

* E2E only, as before issue 15 (``Receiver().receive(msg)``: no cycle time, no rate check);
* E2E + rate + sequence checks (``receive(msg, t_s)``), i.e. the keyless ECU;
* the same + SecOC: each message is a protected frame held until its authenticator, whose
  arrival verifies the CMAC (``cryptography``) and the freshness, then runs every E2E check.

Figures are medians over batches of 99 messages; the SecOC line gives the cost per
protected message (its two frames) and per wire frame (half that). Signing an
authenticator is timed too. The machine is shared: run it twice and compare.

``--closed-loop``: also the paper scenario (tightening, in process) with E2E only and with
SecOC, alternating, best of 3 each: what authentication costs the whole loop (every
authenticator is one more frame through python-can's virtual bus, which dominates).
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

from can_dbc import CounterSequence, Receiver, SecOcSender, SecOcVerifier, encode

SIGNALS = {
    "WheelSpeeds": {"WheelSpeedFL": 81.2, "WheelSpeedFR": 81.25, "WheelSpeedRL": 80.9, "WheelSpeedRR": 81.0},
    "DriverInput": {"AccelPedal": 100.0, "BrakePedal": 0.0, "SteeringWheelAngle": -3.5, "SteeringWheelRate": 0.0},
    "ObjectTrack": {"ObjectValid": 1, "ObjectRange": 120.34, "ObjectRangeRate": -22.5, "ObjectLateral": 0.2},
}
NAMES = tuple(SIGNALS)
BATCH_CYCLES = 45  # 45 cycles: 45 + 45 + 9 = 99 messages at the DBC rates


def _stream(cycles: int, signer: SecOcSender) -> list[tuple[float, object, object]]:
    """(t_s, frame, authenticator) at the DBC rates: 10 ms, 10 ms, 50 ms."""
    counters = {name: CounterSequence() for name in NAMES}
    out = []
    for k in range(cycles):
        for name in NAMES:
            if name == "ObjectTrack" and k % 5:
                continue
            msg = encode(name, SIGNALS[name], counters[name].next())
            out.append((k * 0.01, msg, signer.authenticator(msg)))
    return out


def _timed(stream, receive) -> list[float]:
    """Median-ready list: µs per message of each batch."""
    per_batch = []
    for start in range(0, len(stream) - 98, 99):
        batch = stream[start:start + 99]
        t0 = time.perf_counter_ns()
        for item in batch:
            receive(item)
        per_batch.append((time.perf_counter_ns() - t0) / 99 / 1000.0)
    return per_batch


def bench(messages: int) -> dict[str, float]:
    key = os.urandom(16)
    signer = SecOcSender(key)
    stream = _stream(messages // 99 * BATCH_CYCLES, signer)
    plain, checked = Receiver(names=NAMES), Receiver(names=NAMES)
    keyed = Receiver(names=NAMES, secoc=SecOcVerifier(key))

    def secured(item):
        t_s, msg, auth = item
        keyed.receive(msg, t_s)
        if keyed.receive(auth, t_s) is None:
            raise AssertionError("a genuine message was not accepted")

    sign_signer = SecOcSender(key)
    result = {
        "e2e_us": statistics.median(_timed(stream, lambda i: plain.receive(i[1]))),
        "checks_us": statistics.median(_timed(stream, lambda i: checked.receive(i[1], i[0]))),
        "secoc_message_us": statistics.median(_timed(stream, secured)),
        "sign_us": statistics.median(_timed(stream, lambda i: sign_signer.authenticator(i[1]))),
    }
    result["secoc_frame_us"] = result["secoc_message_us"] / 2.0
    result["accepted"] = keyed.stats["authenticated"]
    result["rejected"] = sum(v for k, v in keyed.stats.items() if k.endswith("Error") or k == "UnknownFrame")
    return result


def closed_loop(repeats: int = 3) -> dict[bool, float]:
    """Best wall time (s) of the paper's tightening run in process, without and with SecOC."""
    from cosim.link.ecu_link import EcuOptions
    from cosim.loop.master import run_scenario
    from cosim.cli.paper import PAPER_SCENARIO
    from cosim.scenarios.loader import load_scenario
    from fmu_plant.build import ensure_fmu

    scenario, fmu = load_scenario(PAPER_SCENARIO), ensure_fmu(fmi_version=3)
    best = {False: float("inf"), True: float("inf")}
    for _ in range(repeats):
        for auth in (False, True):
            record = run_scenario(scenario, fmu, "tightening", ecu=EcuOptions(authenticate=auth))
            best[auth] = min(best[auth], record.metrics.wall_time_s)
            sim_s = record.metrics.sim_time_s
    return {"sim_s": sim_s, **{f"wall_{a}": w for a, w in best.items()}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--messages", type=int, default=99_000)
    parser.add_argument("--closed-loop", action="store_true", help="also time the paper run with and without SecOC")
    args = parser.parse_args()
    r = bench(args.messages)
    print(f"receive, E2E only (before issue 15)      : {r['e2e_us']:.2f} µs/frame median")
    print(f"receive, E2E + rate + sequence checks    : {r['checks_us']:.2f} µs/frame median")
    print(f"receive, all checks + SecOC, per message : {r['secoc_message_us']:.2f} µs median (frame + authenticator)")
    print(f"receive, all checks + SecOC, per frame   : {r['secoc_frame_us']:.2f} µs median (goal <= 20)")
    print(f"sign an authenticator (CMAC-AES-128)     : {r['sign_us']:.2f} µs median")
    print(f"authenticated {r['accepted']}, rejected {r['rejected']}")
    if args.closed_loop:
        c = closed_loop()
        print(f"paper run (tightening, {c['sim_s']:.0f} s simulated, in process), best of 3: E2E only "
              f"{c['wall_False']:.2f} s ({c['sim_s'] / c['wall_False']:.0f}x real time), with SecOC "
              f"{c['wall_True']:.2f} s ({c['sim_s'] / c['wall_True']:.0f}x); ratio {c['wall_True'] / c['wall_False']:.2f}")


if __name__ == "__main__":
    main()
