"""The leanest pure-Python form of one closed-loop cycle's required work (issue 10: can 300x be reached?).

:class:`LeanLoop` runs the paper run's cycles doing every operation the loop must do on every
frame and every cycle, SecOC on, written out with no layers: one Python call per frame and
operation (pack + sign, verify + check), one per side and cycle, and none deeper. Per 10 ms cycle:

* plant: the FMU's raw set + ``doStep`` (10 ms) + get (fmpy's ctypes functions, as
  :class:`cosim.world.plant_fmu.FmuPlant` binds them), outputs to SI, the NaN/Inf check;
* world: the gap to a lead object, the radar's truth and its latency queue, the driver's pedals;
* master -> ECU: ``DriverInput`` and ``WheelSpeeds`` every cycle, ``ObjectTrack`` every 5th,
  each packed (range-checked), counter and E2E CRC-8 set, built as a ``can.Message``, signed
  (CMAC-AES-128 over data ID | frame | freshness, ``cryptography``) and put on a deque;
* ECU: every frame taken off the deque; an authenticator's freshness reconstructed and its MAC
  verified; the protected frame's DLC, CRC, counter (sequence) and rate (arrival window)
  checked, its signals decoded and range-checked, converted to SI and latched; each input's
  rate fault, the core's inputs built and the REAL core step (:func:`ecu.core.step`) run;
  ``SafetyOverride`` packed, signed and sent, ``EcuStatus`` every 10th cycle;
* gateway: the ``SafetyOverride`` pair verified and checked like the ECU's inputs, the
  actuation (min/max of pedals and override);
* log: each frame as a ``LoggedFrame`` (bytes of its data), the cycle's row, the metrics' extremes.

What it leaves out, because it never happens in the paper run's good path: error messages, events,
fallbacks, resynchronisation. What it does not keep: python-can's ``BusABC`` (a deque instead), the
codec's signal dicts (tuples in table order), configuration objects. So its time per cycle is close to
a lower bound for any design in pure Python that keeps every check; with the 33.3 µs budget of 300x it
says how much room is left for structure (classes, seams, the ``BusABC`` interface, error handling).
Not squeezed further: the signals are packed and unpacked by loops over the codec's tables; straight-
line code generated per message measured about 0.1 µs a frame faster (WheelSpeeds packing 0.70
instead of 0.80 µs, timeit), about 0.7 µs a cycle.
"""

from __future__ import annotations

import struct
import time
from collections import deque

import can
import numpy as np
from cryptography.hazmat.primitives.ciphers import algorithms
from cryptography.hazmat.primitives.cmac import CMAC

from can_dbc import AUTHENTICATORS, LAYOUTS
from can_dbc.crc import _TABLE
from cosim.results.run_record import LoggedFrame
from cosim.world.plant_fmu import FmuPlant
from ecu.core import CoreInputs, CoreState, step as core_step

_new = tuple.__new__
_MAC_INPUT = struct.Struct(">H8sQ").pack  # data ID | 8-byte frame | freshness value (can_dbc.secoc)
_MSG = can.Message
_WHEEL_MAX_KMH = LAYOUTS["WheelSpeeds"].signals[0].maximum
_WINDOW = 10  # rate monitor: arrivals per window of 10 cycle times, at most 25 (can_dbc.rate)


class _Tx:
    """A sent message: its packing table, CRC seed, counter and freshness value."""

    __slots__ = ("fid", "auth_id", "table", "seed", "counter", "fv")

    def __init__(self, name: str, auth_id: int | None) -> None:
        layout = LAYOUTS[name]
        self.fid, self.auth_id, self.table, self.seed = layout.frame_id, auth_id, layout.pack_table, layout.crc_seed
        self.counter = self.fv = 0


class _Rx:
    """A received message: unpacking table, CRC seed, held frame, counter, score, arrival times."""

    __slots__ = ("fid", "table", "seed", "held", "counter", "score", "sync", "times", "fv", "cycle_s")

    def __init__(self, name: str) -> None:
        layout = LAYOUTS[name]
        self.fid, self.table, self.seed = layout.frame_id, layout.unpack_table, layout.crc_seed
        self.held, self.counter, self.score, self.sync, self.fv = None, None, 0, 0, -1
        self.cycle_s = layout.cycle_time_ms / 1000.0
        self.times: deque[float] = deque(maxlen=26)


def pack(tx: _Tx, values: tuple) -> bytearray:
    """Pack ``values`` (table order) with range checks, set counter and CRC: the frame's 8 bytes."""
    payload = tx.counter << 8
    for (_, start, mask, scale, offset, raw_min, raw_max), value in zip(tx.table, values):
        raw = round((value - offset) / scale)
        if raw < raw_min or raw > raw_max:
            raise ValueError(f"0x{tx.fid:X}: {value} out of range")
        payload |= (raw & mask) << start
    d = bytearray(payload.to_bytes(8, "little"))
    t = _TABLE
    d[0] = t[t[t[t[t[t[t[tx.seed ^ d[1]] ^ d[2]] ^ d[3]] ^ d[4]] ^ d[5]] ^ d[6]] ^ d[7]]
    tx.counter = (tx.counter + 1) % 15
    return d


def pack_sign(tx: _Tx, values: tuple, mac, out: list) -> None:
    """:func:`pack` ``values``, then build the frame and its authenticator."""
    d = pack(tx, values)
    cmac = mac()
    cmac.update(_MAC_INPUT(tx.fid, d, tx.fv))
    auth = bytearray((tx.fv & 0xFFFF).to_bytes(2, "little")) + cmac.finalize()[:6]
    tx.fv += 1
    out += (_MSG(0.0, tx.fid, False, False, False, None, 8, d), _MSG(0.0, tx.auth_id, False, False, False, None, 8, auth))


def verify_check(rx: _Rx, auth: bytearray, mac, t_s: float) -> tuple | None:
    """Verify the held frame against ``auth``, check DLC, CRC, counter and rate; decode it."""
    msg, rx.held = rx.held, None
    d = msg.data
    fv = rx.fv + 1 + (((auth[0] | auth[1] << 8) - rx.fv - 1) & 0xFFFF)
    cmac = mac()
    cmac.update(_MAC_INPUT(rx.fid, d, fv))
    if msg.dlc != 8 or len(d) != 8 or msg.is_fd or cmac.finalize()[:6] != auth[2:8]:
        raise ValueError("authentication or length")
    rx.fv = fv
    t = _TABLE
    if t[t[t[t[t[t[t[rx.seed ^ d[1]] ^ d[2]] ^ d[3]] ^ d[4]] ^ d[5]] ^ d[6]] ^ d[7]] != d[0]:
        raise ValueError("CRC")
    counter = d[1] & 0x0F
    delta = 1 if rx.counter is None else (counter - rx.counter) % 15
    rx.counter = counter
    if delta != 1 or rx.sync:
        raise ValueError("sequence")  # never taken in the paper run
    times = rx.times
    if times and t_s - times[-1] > 5 * rx.cycle_s + 1e-6:
        times.clear()
    times.append(t_s)
    if len(times) > 25 and t_s - times[0] < _WINDOW * rx.cycle_s - 1e-6:
        raise ValueError("too fast")
    if rx.score:
        rx.score -= 1
    payload, values = int.from_bytes(d, "little"), []
    for _, start, mask, sign_bit, raw_min, raw_max, scale, offset, is_integer, choices in rx.table:
        raw = (payload >> start) & mask
        if raw & sign_bit:
            raw -= mask + 1
        if raw < raw_min or raw > raw_max or (choices and raw not in choices):
            raise ValueError("range")
        values.append(raw if is_integer else raw * scale + offset)
    return values


class LeanLoop:
    """The paper run's closed loop in its leanest form (see the module docstring); :meth:`run` times it."""

    def __init__(self, sc, fmu, params, key: bytes, status_strategy: int) -> None:
        self.plant = FmuPlant(sc.plant, fmu)
        p = self.plant  # noqa: SLF001 below: its raw calls are what the leanest form uses
        self.fmu = (p._set, p._set_in, p._raw_step, p._component, p._step_tail, p._get, p._get_out, p._out_val)
        roles = {role: (i, scale, offset) for i, role, scale, offset in p._actuated}
        self.throttle_in, self.brake_in, self.in_val = roles["throttle"], roles["brake"], p._in_val
        self.conv = p._read_conv
        obj = sc.scene_objects()[0]
        self.obj = (obj.position_m, obj.speed_mps, sc.plant.front_bumper_offset_m)
        self.radar = deque(maxlen=int(round(sc.radar.latency_s / 0.01)) + 1)
        self.mac = CMAC(algorithms.AES(key)).copy
        auth = {name: AUTHENTICATORS[name] for name in ("DriverInput", "WheelSpeeds", "ObjectTrack",
                                                                     "SafetyOverride")}
        self.tx = {name: _Tx(name, auth.get(name)) for name in ("DriverInput", "WheelSpeeds", "ObjectTrack")}
        self.ecu_tx, self.ecu_status = _Tx("SafetyOverride", auth["SafetyOverride"]), _Tx("EcuStatus", None)
        self.status_layout = LAYOUTS["EcuStatus"]  # the gateway's check of it
        self.ecu_rx = {auth[n]: _Rx(n) for n in ("WheelSpeeds", "DriverInput", "ObjectTrack")}
        self.held = {rx.fid: rx for rx in self.ecu_rx.values()}
        self.rows_rx = tuple(self.ecu_rx.values())  # WheelSpeeds, DriverInput, ObjectTrack
        self.rng, self.last_override_s = np.random.default_rng(sc.scenario.seed), 0.0
        self.gw_rx, self.gw_auth = _Rx("SafetyOverride"), auth["SafetyOverride"]
        self.strategy = status_strategy
        self.to_ecu, self.to_master, self.frames, self.rows = deque(), deque(), [], []
        self.params, self.state = params, CoreState()
        self.latch = [(0.0, 0.0, 0.0, 0.0), 0.0, 0.0, False, 0.0, 0.0, 0.0, -1e9, -1e9, -1e9]
        self.actuation, self.min_gap, self.max_speed = (0.0, 0.0), float("inf"), 0.0

    def plant_world(self, k: int) -> tuple:
        """Set the inputs, step 10 ms, read and convert the outputs; the world's truth and the radar queue."""
        set_, set_in, raw_step, comp, tail, get, get_out, out_val = self.fmu
        (ti, ts, to), (bi, bs, bo), val = self.throttle_in, self.brake_in, self.in_val
        val[ti], val[bi] = self.actuation[0] * ts + to, self.actuation[1] * bs + bo
        if set_(*set_in) > 1 or raw_step(comp, k * 0.01, 0.01, *tail) > 1 or get(*get_out) > 1:
            raise RuntimeError("FMU call failed")
        raw = out_val[:]
        (ip, sp, op), (iv, sv, ov), acc, ((j0, s0, o0), (j1, s1, o1), (j2, s2, o2), (j3, s3, o3)) = self.conv
        pos, v = raw[ip] * sp + op, raw[iv] * sv + ov
        a = 0.0 if acc is None else raw[acc[0]] * acc[1] + acc[2]
        w = (raw[j0] * s0 + o0, raw[j1] * s1 + o1, raw[j2] * s2 + o2, raw[j3] * s3 + o3)
        s = pos + v + a + w[0] + w[1] + w[2] + w[3]
        if s - s != 0.0:
            raise RuntimeError("NaN or Inf from the plant")
        x0, v_obj, bumper_offset_m = self.obj
        gap = x0 + v_obj * k * 0.01 - (pos + bumper_offset_m)
        self.radar.append((gap, v_obj - v, 0.0) if 0.0 < gap <= 200.0 else None)
        return pos, v, a, w, gap

    def master_out(self, k: int, v: float, w: tuple) -> list:
        """This cycle's input frames and their authenticators, onto the ECU's queue."""
        out, mac, tx = [], self.mac, self.tx
        pack_sign(tx["DriverInput"], (100.0, 0.0, 0.0), mac, out)
        top, w0, w1, w2, w3 = _WHEEL_MAX_KMH, w[0] * 3.6, w[1] * 3.6, w[2] * 3.6, w[3] * 3.6
        pack_sign(tx["WheelSpeeds"], (min(top, max(0.0, w0)), min(top, max(0.0, w1)), min(top, max(0.0, w2)),
                                      min(top, max(0.0, w3))), mac, out)
        if k % 5 == 0:
            noise_r, noise_rr = self.rng.standard_normal(2).tolist()  # drawn every update, as RadarModel does
            dropped = self.rng.random() < 0.0
            truth = self.radar[0] if len(self.radar) == self.radar.maxlen and not dropped else None
            track = (1, min(max(truth[0] + 0.0 * noise_r, 0.0), 250.0), min(max(truth[1] + 0.0 * noise_rr, -100.0),
                                                                            100.0), truth[2]) \
                if truth is not None else (0, 0.0, 0.0, 0.0)
            pack_sign(tx["ObjectTrack"], track, mac, out)
        self.to_ecu.extend(out)
        return out

    def ecu(self, t_s: float) -> list:
        """Drain the ECU's queue (verify, check, decode, latch), build the inputs, step the core, send."""
        queue, held, by_auth, mac, latch = self.to_ecu, self.held, self.ecu_rx, self.mac, self.latch
        while queue:
            msg = queue.popleft()
            fid = msg.arbitration_id
            if fid in held:
                held[fid].held = msg
                continue
            rx = by_auth[fid]
            s = verify_check(rx, msg.data, mac, t_s)
            if rx.fid == 0xA0:  # WheelSpeeds, km/h -> m/s
                latch[0], latch[7] = (s[0] / 3.6, s[1] / 3.6, s[2] / 3.6, s[3] / 3.6), t_s
            elif rx.fid == 0xB0:  # DriverInput, % -> fraction
                latch[1], latch[2], latch[8] = s[0] / 100.0, s[1] / 100.0, t_s
            else:  # ObjectTrack
                latch[3], latch[4], latch[5], latch[6], latch[9] = bool(s[0]), s[1], s[2], s[3], t_s
        wheel_rx, driver_rx, object_rx = self.rows_rx
        wheels, accel, brake, valid, range_m, rate, lateral, wt, dt, ot = latch
        inputs = _new(CoreInputs, (t_s, wheels, accel, brake, valid, range_m, rate, wt, dt, ot, wheel_rx.score,
                                   driver_rx.score, object_rx.score, lateral, _rate_fault(wheel_rx, t_s),
                                   _rate_fault(driver_rx, t_s), _rate_fault(object_rx, t_s), 0))
        self.state, o = core_step(self.state, inputs, self.params)
        out = []
        pack_sign(self.ecu_tx, (int(o.mode), int(o.override_active), o.throttle_limit_pct,
                                o.brake_decel_request_mps2), mac, out)
        if round(t_s * 100) % 10 == 0:
            out.append(self._status(o))
        self.to_master.extend(out)
        return out

    def _status(self, o) -> can.Message:
        """``EcuStatus`` (every 10th cycle): strategy, three clamped values and the 13 fault bits."""
        tx = self.ecu_status
        values = (self.strategy, min(1.0, max(0.0, o.proximity)), min(250.0, max(0.0, o.stopping_distance_m)),
                  min(100.0, max(0.0, o.speed_estimate_mps)), *((o.fault_flags >> b) & 1 for b in range(13)))
        return _MSG(0.0, tx.fid, False, False, False, None, 8, pack(tx, values))

    def gateway_log(self, t_s: float, sample: tuple, sent: list, received: list) -> None:
        """The gateway takes the ECU's frames and computes the next actuation; the cycle is logged."""
        queue, rx, throttle, brake, mode = self.to_master, self.gw_rx, 1.0, 0.0, 0  # full-throttle driver
        overrides = 0
        while queue:
            msg = queue.popleft()
            if msg.arbitration_id == rx.fid:
                rx.held = msg
            elif msg.arbitration_id == self.gw_auth:
                mode, active, limit_pct, decel = verify_check(rx, msg.data, self.mac, t_s)
                overrides += 1
                self.last_override_s = t_s
                if active:
                    throttle = min(throttle, limit_pct / 100.0)
                brake = min(1.0, max(brake, decel / 10.0))
            else:  # EcuStatus: CRC and counter checked, fault bits decoded (never set here)
                _status_check(self.status_layout, msg.data)
        if overrides > 1 or t_s - self.last_override_s > 0.1 or rx.score >= 5:  # second ECU, timeout, E2E
            throttle, brake = 1.0, 0.0
        self.actuation = (throttle, brake)
        append = self.frames.append
        for msg in sent:
            append(_new(LoggedFrame, (t_s, msg.arbitration_id, bytes(msg.data))))
        for msg in received:
            append(_new(LoggedFrame, (t_s, msg.arbitration_id, bytes(msg.data))))
        pos, v, a, _, gap = sample
        self.rows.append((t_s, pos, v, a, throttle, brake, mode, gap, 100.0, 0.0))
        self.min_gap, self.max_speed = min(self.min_gap, gap), max(self.max_speed, v)

    def run(self, cycles: int) -> float:
        """Run ``cycles`` cycles (or up to contact with the object); CPU µs per cycle."""
        c0, k = time.process_time(), 0
        try:
            for k in range(cycles):
                t_s = k * 0.01
                sample = self.plant_world(k)
                sent = self.master_out(k, sample[1], sample[3])
                self.gateway_log(t_s, sample, sent, self.ecu(t_s))
                if sample[4] <= 0.0:  # contact: the run stops, as the closed loop's does
                    break
        finally:
            self.plant.close()
        return (time.process_time() - c0) / (k + 1) * 1e6


def _rate_fault(rx: _Rx, t_s: float) -> int:
    """The rate monitor's verdict (can_dbc.rate, too slow only: too fast raises on arrival): RATE bit or 0."""
    times, window = rx.times, _WINDOW * rx.cycle_s
    if len(times) < 5 or t_s - times[0] < window - 1e-6 or t_s - times[-1] > 5 * rx.cycle_s + 1e-6:
        return 0
    return 0 if times[-5] > t_s - window + 1e-6 else 1 << 5


def _status_check(layout, d: bytearray) -> list:
    """CRC check and decode of an ``EcuStatus`` (not authenticated)."""
    t = _TABLE
    if t[t[t[t[t[t[t[layout.crc_seed ^ d[1]] ^ d[2]] ^ d[3]] ^ d[4]] ^ d[5]] ^ d[6]] ^ d[7]] != d[0]:
        raise ValueError("CRC")
    payload = int.from_bytes(d, "little")
    return [((payload >> start) & mask) * scale + offset for _, start, mask, _, _, _, scale, offset, _, _
            in layout.unpack_table]
