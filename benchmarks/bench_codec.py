"""Codec figures: encode with E2E, and receive with all checks (median per frame).

Run: ``python benchmarks/bench_codec.py [--frames N]``. Goals (issue 2):
encode <= 10 µs median, receive <= 15 µs median on the 2-core CI machine.
"""

from __future__ import annotations

import argparse
import statistics
import time

from can_dbc import Receiver, encode

SIGNALS = {
    "WheelSpeeds": {"WheelSpeedFL": 81.2, "WheelSpeedFR": 81.25, "WheelSpeedRL": 80.9, "WheelSpeedRR": 81.0},
    "DriverInput": {"AccelPedal": 100.0, "BrakePedal": 0.0, "SteeringWheelAngle": -3.5, "SteeringWheelRate": 0.0},
    "ObjectTrack": {"ObjectValid": 1, "ObjectRange": 120.34, "ObjectRangeRate": -22.5, "ObjectLateral": 0.2},
}


def _median_us(samples_ns: list[int], batch: int) -> float:
    return statistics.median(samples_ns) / batch / 1000.0


def bench(frames: int, batch: int = 100) -> dict[str, float]:
    names = list(SIGNALS)
    enc_ns, rx_ns = [], []
    rx = Receiver()
    counter = 0
    for _ in range(frames // batch):
        msgs = []
        start = time.perf_counter_ns()
        for i in range(batch):
            name = names[i % 3]
            msgs.append(encode(name, SIGNALS[name], (counter + i // 3) % 15))
        enc_ns.append(time.perf_counter_ns() - start)
        counter = (counter + batch // 3 + 1) % 15
        start = time.perf_counter_ns()
        for msg in msgs:
            rx.receive(msg)
        rx_ns.append(time.perf_counter_ns() - start)
    return {"encode_us": _median_us(enc_ns, batch), "receive_us": _median_us(rx_ns, batch),
            "good": rx.stats["good"], "rejected": sum(v for k, v in rx.stats.items() if k != "good")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--frames", type=int, default=200_000)
    args = parser.parse_args()
    result = bench(args.frames)
    print(f"encode with E2E        : {result['encode_us']:.2f} µs/frame median (goal <= 10)")
    print(f"receive with all checks: {result['receive_us']:.2f} µs/frame median (goal <= 15)")
    print(f"frames accepted {result['good']}, rejected {result['rejected']}")


if __name__ == "__main__":
    main()
