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
from typing import Iterable, Mapping, NamedTuple

import can

from .counter import COUNTER_MODULUS, MAX_COUNTER_JUMP, counter_delta
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
from .secoc import AUTH_ID_OF, PROTECTED_ID_OF, SecOcVerifier

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
        self._layouts = {fid: lay for fid, lay in LAYOUTS_BY_ID.items() if lay.name in wanted}
        self._last_counter: dict[str, int] = {}
        self._score: dict[str, int] = {name: 0 for name in wanted}
        self.stats: Counter[str] = Counter()
        self._sync_left: dict[str, int] = {name: 0 for name in wanted}
        self._rates = {name: RateMonitor(LAYOUTS[name].cycle_time_ms / 1000.0)
                       for name in wanted if name in CYCLIC and LAYOUTS[name].cycle_time_ms}
        self._secoc = secoc
        #: protected frame ID -> the frame held until its authenticator arrives
        self._held: dict[int, can.Message | None] = {}
        self._auth_of: dict[int, int] = {}
        if secoc is not None:
            self._auth_of = {PROTECTED_ID_OF[a]: a for fid in self._layouts if (a := AUTH_ID_OF.get(fid))}
            self._held = dict.fromkeys(self._auth_of)

    def score(self, name: str) -> int:
        """Current validity score of message ``name`` (0 good .. 5 invalid)."""
        return self._score[name]

    def is_valid(self, name: str) -> bool:
        """False while the message's validity score is at or above 5."""
        return self._score[name] < SCORE_INVALID

    def rx_flags(self, name: str, t_s: float) -> int:
        """``RX_RATE`` | ``RX_SEQUENCE`` for message ``name`` at cycle time ``t_s`` (0: no receiver fault)."""
        rate = self._rates.get(name)
        flags = RX_RATE if rate is not None and rate.fault(t_s) else 0
        return flags | RX_SEQUENCE if self._sync_left[name] else flags

    def _bad(self, name: str) -> None:
        self._score[name] = min(SCORE_MAX, self._score[name] + 1)

    def check(self, msg: can.Message, t_s: float | None = None) -> Frame | None:
        """Check ``msg`` (received at cycle time ``t_s``, for the rate checks); return the :class:`Frame`.

        Raises a :class:`FrameError`. With ``secoc``, a protected frame returns None: it is held
        until its authenticator, whose arrival returns the protected frame's :class:`Frame`.
        """
        fid = msg.arbitration_id
        layout = self._layouts.get(fid)
        if self._secoc is not None and not (msg.is_extended_id or msg.is_error_frame or msg.is_remote_frame):
            if fid in self._held:
                return self._hold(layout, msg)
            if layout is None and fid in PROTECTED_ID_OF and PROTECTED_ID_OF[fid] in self._held:
                msg, layout = self._authenticate(msg)
        if layout is None or msg.is_extended_id or msg.is_error_frame or msg.is_remote_frame:
            self.stats["UnknownFrame"] += 1
            raise UnknownFrame(
                f"expected an ID of the contract, got 0x{msg.arbitration_id:X}"
                + (" (extended)" if msg.is_extended_id else "")
            )
        name = layout.name
        try:
            frame = self._check_known(layout, msg, t_s)
        except FrameError as exc:
            self.stats[type(exc).__name__] += 1
            self._bad(name)
            raise
        if frame.fresh:  # a good frame, even while resynchronising
            self._score[name] = max(0, self._score[name] - 1)
            self.stats["good"] += 1
        else:
            self._bad(name)
            self.stats["repeated"] += 1
        return frame

    def _hold(self, layout: MessageLayout, msg: can.Message) -> None:
        """Hold a protected frame for its authenticator; one it displaces was never authenticated."""
        displaced = self._held[msg.arbitration_id]
        self._held[msg.arbitration_id] = msg
        if displaced is not None:
            self.stats["AuthError"] += 1
            self._bad(layout.name)
            raise AuthError(f"{layout.name}: frame without an authenticator (displaced by the next one)")
        return None

    def _authenticate(self, auth: can.Message) -> tuple[can.Message, MessageLayout]:
        """Verify ``auth`` against the held frame; returns that frame and its layout to check."""
        fid = PROTECTED_ID_OF[auth.arbitration_id]
        layout = self._layouts[fid]
        held = self._held[fid]
        self._held[fid] = None
        try:
            if held is None:
                raise AuthError(f"{layout.name}: authenticator without a frame to authenticate")
            self._secoc.verify(fid, held.data, auth.data)
        except AuthError as exc:
            self.stats[type(exc).__name__] += 1
            self._bad(layout.name)
            raise
        self.stats["authenticated"] += 1
        return held, layout

    def _sequence(self, name: str, delta: int) -> bool:
        """Update the sync state for a counter step ``delta``; True when the frame may be used."""
        left = self._sync_left[name]
        if delta == 0 or delta > MAX_COUNTER_JUMP:
            self._sync_left[name] = SYNC_FRAMES
            return False
        if left:
            left = left - 1 if delta == 1 else SYNC_FRAMES
            self._sync_left[name] = left
            return left == 0
        return True

    def _check_known(self, layout: MessageLayout, msg: can.Message, t_s: float | None = None) -> Frame:
        data = msg.data
        if msg.dlc != FRAME_LENGTH or len(data) != FRAME_LENGTH or msg.is_fd:
            raise LengthError(
                f"{layout.name}: expected DLC {FRAME_LENGTH}, got {msg.dlc} ({len(data)} data bytes)"
            )
        crc = e2e_p01_crc8(layout.crc_seed, data)
        if crc != data[0]:
            raise ChecksumError(f"{layout.name}: expected CRC 0x{crc:02X}, got 0x{data[0]:02X}")
        counter = data[1] & 0x0F
        if counter >= COUNTER_MODULUS:
            raise CounterError(f"{layout.name}: expected counter 0..14, got {counter}")
        name = layout.name
        if t_s is not None and (rate := self._rates.get(name)) is not None:
            rate.arrive(t_s)
        previous = self._last_counter.get(name)
        self._last_counter[name] = counter  # follow the new counter, but only after SYNC_FRAMES good ones
        delta = 1 if previous is None else counter_delta(previous, counter)
        synced = self._sequence(name, delta)
        if delta > MAX_COUNTER_JUMP:
            raise CounterError(
                f"{name}: expected counter {(previous + 1) % COUNTER_MODULUS}"
                f" (jump <= {MAX_COUNTER_JUMP}), got {counter}"
            )
        try:
            signals = _decode(layout, int.from_bytes(data, "little"))
        except FrameError:
            raise
        except Exception as exc:  # noqa: BLE001 - any decode failure is a frame error
            raise DecodeError(f"{name}: cannot decode payload {bytes(data).hex()}: {exc}") from exc
        return Frame(name, signals, counter, delta != 0, synced)

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
