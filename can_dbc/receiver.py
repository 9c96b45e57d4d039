"""The receiving side of the contract: every frame checked, in a fixed order.

Checks, in this order (issue 2): (1) known ID, (2) exact DLC, (3) E2E CRC,
(4) E2E counter — a repeat means no new data, a jump of more than 2 is an
error, (5) decode, (6) every signal within its DBC [min, max], (7) enumeration
values declared with ``VAL_``.

Validity score per message, in the manner of openpilot/panda's safety
(``MAX_WRONG_COUNTERS``): +1 for a bad frame or a repeated counter, −1 for a
good fresh frame, clamped to 0..5. A message is invalid while its score is
>= 5. Unknown IDs are counted and ignored: they never reach the caller's loop
as an exception from :meth:`Receiver.receive`.

Receiver checks in the manner of AUTOSAR's E2E state machine (issue 15):

* sequence: a repeated or jumping counter puts the message into *sync*:
  its frames are checked but not delivered (``Frame.synced`` False,
  :meth:`receive` returns None) until ``SYNC_FRAMES`` (3) consecutive frames
  each advance the counter by exactly 1. One valid-CRC frame therefore no
  longer re-synchronises the receiver to a foreign or replayed stream, and two
  interleaved senders keep the message in sync (invalid) for as long as they
  both send;
* frequency: given the cycle time ``t_s`` of each arrival, every cyclic
  message is rate-monitored (:mod:`can_dbc.rate`);
* :meth:`rx_flags` reports both per message (``RX_RATE``, ``RX_SEQUENCE``);
* authentication (``secoc``, :mod:`can_dbc.secoc`): a protected frame is
  held until its authenticator frame arrives and is checked only after its
  MAC and freshness verify; a forged, replayed or unauthenticated frame is
  rejected (``AuthError``/``FreshnessError``, counted) and never touches the
  E2E state.
"""

from __future__ import annotations

from collections import Counter
from typing import Iterable, Mapping, NamedTuple, NoReturn

import can

from .counter import COUNTER_MODULUS, MAX_COUNTER_JUMP
from .crc import e2e_p01_crc8
from .database import CYCLIC, FRAME_LENGTH, LAYOUTS, LAYOUTS_BY_ID, MessageLayout
from .errors import (
    AuthError,
    ChecksumError,
    CounterError,
    DecodeError,
    EnumError,
    FrameError,
    LengthError,
    RangeError,
    UnknownFrame,
)
from .rate import RateMonitor
from .secoc import AUTH_ID_OF, SecOcVerifier

SCORE_MAX = 5
SCORE_INVALID = 5
#: consecutive in-sequence frames (counter + 1 each) needed after a sequence error
SYNC_FRAMES = 3
#: :meth:`Receiver.rx_flags` bits
RX_RATE = 1
RX_SEQUENCE = 2


class Frame(NamedTuple):
    """A frame that passed every check. ``signals`` are in DBC units.

    A tuple: one is built per received frame, and a ``NamedTuple`` is about
    four times cheaper to build (0.5 instead of 2.0 µs, measured) than the
    frozen dataclass it replaces.
    """

    name: str
    #: read only: the frames of one payload share it (``_DECODED``)
    signals: Mapping[str, float]
    counter: int
    fresh: bool
    #: False while the message resynchronises after a sequence error (data not to be used)
    synced: bool = True


def _decode(layout: MessageLayout, payload: int) -> dict[str, float]:
    """Signals (DBC units) of the 64-bit little-endian ``payload``; raises Range/EnumError."""
    values: dict[str, float] = {}
    for name, start, mask, sign_bit, raw_min, raw_max, scale, offset, is_integer, choices in layout.unpack_table:
        raw = (payload >> start) & mask
        if raw & sign_bit:
            raw -= mask + 1
        if raw < raw_min or raw > raw_max:
            sig = next(sig for sig in layout.signals if sig.name == name)
            raise RangeError(f"{layout.name}.{name}: expected {sig.minimum}..{sig.maximum}, got {raw * scale + offset:g}")
        if choices and raw not in choices:
            raise EnumError(f"{layout.name}.{name}: expected one of {sorted(choices)}, got {raw}")
        values[name] = raw if is_integer else raw * scale + offset
    return values


#: per frame ID: payloads that passed the CRC and decoded -> their signals (shared, read-only: ``Frame.signals``).
#: Most frames repeat an earlier payload (a constant content comes round with the counter every 15 frames:
#: the empty ``RadarTrack`` slots, the inactive ``SteeringOverride``, ``SafetyOverride`` outside an
#: intervention, the held pedals), so the CRC and the decode run once per distinct payload, not per frame
#: (measured when every run carried the planar frames: the paper run, tightening: 3,600 decodes for 27,600
#: frames; a remembered ``RadarTrack3`` is checked in 0.8x the time of a new one, timeit in one process).
_DECODED: dict[int, dict[int, Mapping[str, float]]] = {fid: {} for fid in LAYOUTS_BY_ID}
#: payloads remembered per frame ID before the memo starts over (a changing signal fills it in 64 frames)
_DECODED_MAX = 64


def _decoded(known: dict[int, Mapping[str, float]], layout: MessageLayout, payload: int) -> Mapping[str, float]:
    """:func:`_decode` of a payload whose CRC holds, remembered in ``known``; any failure a frame error."""
    try:
        signals = _decode(layout, payload)
    except FrameError:
        raise
    except Exception as exc:  # noqa: BLE001 - any decode failure is a frame error
        raise DecodeError(f"{layout.name}: cannot decode payload {payload.to_bytes(FRAME_LENGTH, 'little').hex()}"
                          f": {exc}") from exc
    if len(known) >= _DECODED_MAX:
        known.clear()
    known[payload] = signals
    return signals


class _Rx:
    """One accepted message's receive state: its layout and E2E/SecOC/rate bookkeeping.

    One row per message, found with ONE dict look-up by frame ID per frame (panda's RX-check
    table); it replaces five dicts keyed by message name that every frame looked up in turn.
    """

    __slots__ = ("layout", "name", "counter", "score", "sync_left", "rate", "protected", "held")

    def __init__(self, layout: MessageLayout, rate: RateMonitor | None, protected: bool) -> None:
        self.layout, self.name, self.rate, self.protected = layout, layout.name, rate, protected
        self.counter: int | None = None  # the last counter seen (followed even while resynchronising)
        self.score = 0
        self.sync_left = 0
        self.held: can.Message | None = None  # SecOC: the frame waiting for its authenticator

    def bad(self) -> None:
        if self.score < SCORE_MAX:
            self.score += 1


def check_alone(msg: can.Message) -> Frame:
    """``msg`` checked on its own merits: known ID, DLC, CRC, counter range, decode, range, enumerations.

    No receive state is read or changed (no counter sequence, rate, score or SecOC): the
    frame is judged as a receiver that has seen nothing before would judge it. For a
    caller that must weigh frames whose *sequence* is in doubt (two senders of one message,
    :mod:`cosim.world.gateway`). Raises a :class:`FrameError`; counts nothing.
    """
    layout = None if msg.is_extended_id else LAYOUTS_BY_ID.get(msg.arbitration_id)
    if layout is None:
        raise UnknownFrame(f"expected an ID of the contract, got 0x{msg.arbitration_id:X}")
    return Receiver._check_known(_Rx(layout, None, False), msg)


class Receiver:
    """Checks frames against the contract and keeps E2E state per message.

    ``names`` restricts the accepted messages (others count as unknown IDs).
    ``secoc``: verify the SecOC authenticators of the protected messages.
    """

    def __init__(self, names: Iterable[str] | None = None, secoc: SecOcVerifier | None = None) -> None:
        wanted = set(LAYOUTS) if names is None else set(names)
        missing = wanted - set(LAYOUTS)
        if missing:
            raise KeyError(f"unknown messages {sorted(missing)}; expected from {sorted(LAYOUTS)}")
        self.stats: Counter[str] = Counter()
        self._secoc = secoc
        self._by_id: dict[int, _Rx] = {}
        #: SecOC: authenticator frame ID -> the state of the message it authenticates
        self._by_auth_id: dict[int, _Rx] = {}
        for fid, layout in LAYOUTS_BY_ID.items():
            if layout.name not in wanted:
                continue
            name, auth_id = layout.name, AUTH_ID_OF.get(fid)
            rate = RateMonitor(layout.cycle_time_ms / 1000.0) if name in CYCLIC and layout.cycle_time_ms else None
            rx = self._by_id[fid] = _Rx(layout, rate, secoc is not None and auth_id is not None)
            if rx.protected and auth_id is not None:
                self._by_auth_id[auth_id] = rx
        self._by_name = {rx.name: rx for rx in self._by_id.values()}

    def score(self, name: str) -> int:
        """Current validity score of message ``name`` (0 good .. 5 invalid)."""
        return self._by_name[name].score

    def is_valid(self, name: str) -> bool:
        """False while the message's validity score is at or above 5."""
        return self._by_name[name].score < SCORE_INVALID

    def rx_flags(self, name: str, t_s: float) -> int:
        """``RX_RATE`` | ``RX_SEQUENCE`` for message ``name`` at cycle time ``t_s`` (0: no receiver fault)."""
        return self.health(name, t_s)[1]

    def health(self, name: str, t_s: float) -> tuple[int, int]:
        """``(score(name), rx_flags(name, t_s))`` in one call: the ECU asks for both, every cycle."""
        rx = self._by_name[name]
        flags = RX_RATE if rx.rate is not None and rx.rate.fault(t_s) else 0
        return rx.score, flags | RX_SEQUENCE if rx.sync_left else flags

    def check(self, msg: can.Message, t_s: float | None = None) -> Frame | None:
        """Check ``msg`` (received at cycle time ``t_s``, for the rate checks); return the :class:`Frame`.

        Raises a :class:`FrameError`. With ``secoc``, a protected frame returns None: it is held
        until its authenticator, whose arrival returns the protected frame's :class:`Frame`.
        """
        fid = msg.arbitration_id
        plain = not (msg.is_extended_id or msg.is_error_frame or msg.is_remote_frame)
        rx = self._by_id.get(fid) if plain else None
        if rx is not None:
            if not rx.protected:
                return self._accept(rx, msg, t_s)
            displaced, rx.held = rx.held, msg  # held for its authenticator
            if displaced is None:
                return None
            self._reject(rx, AuthError(f"{rx.name}: frame without an authenticator (displaced by the next one)"))
        if plain and (rx := self._by_auth_id.get(fid)) is not None:
            return self._accept(rx, self._authenticated(rx, msg), t_s)
        self.stats["UnknownFrame"] += 1
        raise UnknownFrame(f"expected an ID of the contract, got 0x{fid:X}"
                           + (" (extended)" if msg.is_extended_id else ""))

    def _reject(self, rx: _Rx, exc: FrameError) -> NoReturn:
        """Count and score a rejected frame of ``rx``'s message, and raise ``exc``."""
        self.stats[type(exc).__name__] += 1
        rx.bad()
        raise exc

    def _accept(self, rx: _Rx, msg: can.Message, t_s: float | None) -> Frame:
        """:meth:`_check_known` with its outcome counted and scored (a :class:`FrameError` re-raised)."""
        try:
            frame = self._check_known(rx, msg, t_s)
        except FrameError as exc:
            self._reject(rx, exc)
        if frame.fresh:  # a good frame, even while resynchronising
            if rx.score:
                rx.score -= 1
            self.stats["good"] += 1
        else:
            rx.bad()
            self.stats["repeated"] += 1
        return frame

    def _authenticated(self, rx: _Rx, auth: can.Message) -> can.Message:
        """The held frame that ``auth`` authenticates (its MAC and freshness verified), to be checked."""
        held, rx.held = rx.held, None
        try:
            if held is None or self._secoc is None:
                raise AuthError(f"{rx.name}: authenticator without a frame to authenticate")
            self._secoc.verify(rx.layout.frame_id, held.data, auth.data)
        except AuthError as exc:
            self._reject(rx, exc)
        self.stats["authenticated"] += 1
        return held

    @staticmethod
    def _check_known(rx: _Rx, msg: can.Message, t_s: float | None = None) -> Frame:
        """Checks (2) to (7) of the module doc on a frame of a known message, and the sync state."""
        data, layout, name = msg.data, rx.layout, rx.name
        if msg.dlc != FRAME_LENGTH or len(data) != FRAME_LENGTH or msg.is_fd:
            raise LengthError(f"{name}: expected DLC {FRAME_LENGTH}, got {msg.dlc} ({len(data)} data bytes)")
        payload = int.from_bytes(data, "little")
        known = _DECODED[layout.frame_id]
        signals = known.get(payload)  # a payload seen before: its CRC holds and its decode is known
        if signals is None:
            crc = e2e_p01_crc8(layout.crc_seed, data)
            if crc != data[0]:
                raise ChecksumError(f"{name}: expected CRC 0x{crc:02X}, got 0x{data[0]:02X}")
        counter = data[1] & 0x0F
        if counter >= COUNTER_MODULUS:
            raise CounterError(f"{name}: expected counter 0..14, got {counter}")
        if t_s is not None and rx.rate is not None:
            rx.rate.arrive(t_s)
        previous, rx.counter = rx.counter, counter  # follow the new counter, but only after SYNC_FRAMES good ones
        delta = 1 if previous is None else (counter - previous) % COUNTER_MODULUS
        synced = True
        if delta == 0 or delta > MAX_COUNTER_JUMP:  # a repeat or a jump: resynchronise
            rx.sync_left, synced = SYNC_FRAMES, False
            if delta and previous is not None:
                raise CounterError(f"{name}: expected counter {(previous + 1) % COUNTER_MODULUS}"
                                   f" (jump <= {MAX_COUNTER_JUMP}), got {counter}")
        elif rx.sync_left:  # resynchronising: SYNC_FRAMES consecutive frames each stepping by exactly 1
            rx.sync_left = rx.sync_left - 1 if delta == 1 else SYNC_FRAMES
            synced = rx.sync_left == 0
        if signals is None:
            signals = _decoded(known, layout, payload)
        return Frame._make((name, signals, counter, delta != 0, synced))  # length-checked

    def receive(self, msg: can.Message, t_s: float | None = None) -> Frame | None:
        """Like :meth:`check` but never raises: rejected frames are counted, ``None`` returned.

        A repeated counter, a frame while resynchronising and a held protected frame
        return ``None`` too (no new data to use).
        """
        try:
            frame = self.check(msg, t_s)
        except FrameError:
            return None
        return frame if frame is not None and frame.fresh and frame.synced else None
