"""The ECU's steering request reaches the plant, in the closed loop (issue 21).

A planar run (the paper's scene on the road, the driver's wheel held straight), whose ECU asks for
steering: its ``SteeringOverride`` (``ecu.bus_port.steering_message``, replaced here)
ramps to 2 deg from 0.5 s, signed by the ECU with the run's SecOC key as every frame it sends. The
steering gateway accepts it and its overlay reaches the plant's ``steer_request`` input
([plant.inputs], vr 6): the road-wheel angle goes to 2 deg and the car turns left; the ESC frame
carries the plant's own ay and ax outputs. In a second run the ECU requests nothing and a stranger
sends the same requests with a MAC under another key: the gateway refuses and counts each of them,
and the car stays straight, every road-wheel angle, yaw and lateral acceleration exactly 0.
Two 2.5 s runs, a few seconds in all.
"""

import dataclasses
import math

import numpy as np
import pytest

import ecu.node
from can_dbc import DATABASE, CounterSequence, SecOcSender, encode
from cosim.link.ecu_link import EcuOptions
from cosim.loop.master import ClosedLoop
from cosim.scenarios.loader import load_scenario

SCENARIO = "cosim/scenarios/paper_cyclist_road.toml"
START_S, TOP_DEG, STEP_DEG, CYCLE_S = 0.5, 2.0, 0.2, 0.01  # 20 deg/s, within the DBC's rate limit
#: the builtin plant's outputs read after every step: delta, yaw, ay, ax
WATCHED_VRS = [25, 20, 22, 26]
ESC_ID = DATABASE.get_message_by_name("EscDynamics").frame_id


def request(counter: int, cycle: int):
    """The SteeringOverride of ``cycle``: 0 before START_S, then rising by STEP_DEG a cycle to TOP_DEG."""
    angle = min(TOP_DEG, STEP_DEG * (cycle - round(START_S / CYCLE_S) + 1))
    return encode("SteeringOverride", {"SteerActive": int(angle > 0.0), "SteerAngleRequest": max(0.0, angle)},
                  counter)


def steered_run(fmu, monkeypatch, by_ecu: bool):
    """The run with the requests sent by the ECU (``by_ecu``) or by a forger; the steering gateway's counts,
    the record, the watched outputs after every plant step (ms, delta, yaw, ay, ax) and the forged frames."""
    sc = load_scenario(SCENARIO)
    sc = dataclasses.replace(sc, scenario=dataclasses.replace(sc.scenario, duration_s=2.5))
    if by_ecu:
        calls = iter(range(10**6))
        monkeypatch.setattr(ecu.node, "steering_message", lambda outputs, counter: request(counter, next(calls)))
    loop = ClosedLoop(sc, fmu, ecu=EcuOptions(authenticate=True))
    forger, seq, forged = SecOcSender(bytes(16)), CounterSequence(), []
    collect, step, slave = loop.link.collect, loop.plant.step, loop.plant._fmu

    def with_forgeries(t_s, cycle, *rest):
        frames = collect(t_s, cycle, *rest)
        if not by_ecu and t_s >= START_S:
            msg = request(seq.next(), cycle)
            forged.append(msg)
            frames = [*frames, msg, forger.authenticator(msg)]
        return frames

    seen = []

    def watched_step(t_s, h_s):
        step(t_s, h_s)
        seen.append((round((t_s + h_s) * 1000), *slave.getFloat64(WATCHED_VRS)))

    loop.link.collect, loop.plant.step = with_forgeries, watched_step
    record = loop.run()
    return loop.steering_gateway.stats, record, np.array(seen), len(forged)


@pytest.fixture(scope="module")
def fmu():
    from fmu_plant.build import ensure_fmu

    return ensure_fmu(fmi_version=3)


def test_an_accepted_steering_override_turns_the_plants_road_wheel(fmu, monkeypatch):
    stats, record, seen, _ = steered_run(fmu, monkeypatch, by_ecu=True)
    assert stats["good"] == 250 and stats.get("AuthError", 0) == 0  # one a cycle
    delta, yaw = seen[:, 1], seen[:, 2]
    assert (delta[seen[:, 0] <= START_S * 1000] == 0.0).all()
    assert delta[-1] == pytest.approx(math.radians(TOP_DEG), rel=1e-3) and yaw[-1] > 0.0
    # the ESC frame: the plant's ay and ax at the cycle's start, to the DBC's resolution
    by_ms = {int(row[0]): row for row in seen}
    esc = [(f.t_s, DATABASE.decode_message(ESC_ID, f.data)) for f in record.frames if f.arbitration_id == ESC_ID]
    checked = 0
    for t_s, sig in esc:
        row = by_ms.get(round(t_s * 1000))
        if row is not None and t_s > 1.0:
            assert sig["LateralAccel"] == pytest.approx(row[3], abs=0.006)
            assert sig["LongitudinalAccel"] == pytest.approx(row[4], abs=0.006)
            checked += 1
    assert checked > 100 and max(abs(s["LateralAccel"]) for _, s in esc) > 0.5


def test_a_refused_steering_override_leaves_the_car_straight(fmu, monkeypatch):
    stats, record, seen, forged = steered_run(fmu, monkeypatch, by_ecu=False)
    assert stats["AuthError"] == forged == 200  # every forgery refused and counted; the ECU's own accepted
    assert stats["good"] == 250
    assert (seen[:, 1:4] == 0.0).all()  # road-wheel angle, yaw, lateral acceleration
