"""The core's frozen records: inputs, state and outputs of one 10 ms cycle.

All quantities are SI (m, m/s, m/s^2, s); pedals are fractions 0..1; the
``*_rx_t_s`` fields are the times at which the latest *fresh* frame of each
input was received (``-inf`` before the first one), and the ``*_e2e_score``
fields are the codec's E2E validity scores (0 good .. 5 invalid). The shell
converts DBC units to these at the codec boundary.

They are ``NamedTuple``s: immutable like frozen dataclasses, and built about
three times faster, which matters at three records per 10 ms cycle. Build
them by field name (a field added later cannot shift the others); change one
field with ``record._replace(field=value)``.

The modes and the fault bits are the DBC's: :data:`Mode` is
``SafetyOverride.Mode``'s ``VAL_`` table and :data:`FaultFlag` names
``EcuStatus``'s ``Fault*`` signals in bit order (``FaultWheelSpeedTimeout`` ->
``WHEEL_SPEED_TIMEOUT``, bit k at DBC bit 50 + k).
"""

from __future__ import annotations

import math
import re
from enum import IntEnum
from typing import NamedTuple

from can_dbc.contract import FAULT_SIGNALS, MODE_NAMES
from can_dbc.planar import Track

from .decel_estimate import DecelEstimate
from .track_confirmation import TrackState

NEVER_S = -math.inf
#: cycle counters of the state saturate here
CYCLES_MAX = 1_000_000

#: ``SafetyOverride.Mode`` of the DBC, built from its ``VAL_``: STANDBY, TIGHTENING, CONTINGENCY, FAULT.
Mode = IntEnum("Mode", {name: value for value, name in MODE_NAMES.items()}, module=__name__)


def _flag_name(signal_name: str) -> str:
    """``FaultWheelSpeedTimeout`` -> ``WHEEL_SPEED_TIMEOUT`` (``FaultE2E`` -> ``E2E``)."""
    return re.sub(r"(?<=[a-z])(?=[A-Z])", "_", signal_name.removeprefix("Fault")).upper()


#: Fault bit numbers: bit k is ``EcuStatus``'s k-th ``Fault*`` signal (:data:`can_dbc.contract.FAULT_SIGNALS`).
FaultFlag = IntEnum("FaultFlag", {_flag_name(name): bit for bit, name in enumerate(FAULT_SIGNALS)}, module=__name__)
#: the receiver's findings (rate and sequence) that make an input unusable
RECEIVER_FLAGS = (1 << FaultFlag.RATE) | (1 << FaultFlag.SEQUENCE)

#: flags reported in EcuStatus that do not by themselves make the ECU leave its mode: a rejected
#: forged frame leaves the authenticated stream trustworthy (see ecu/README.md, degraded mode)
REPORT_ONLY_FLAGS = 1 << FaultFlag.AUTH


class CoreInputs(NamedTuple):
    """What the ECU knows at cycle time ``t_s``."""

    t_s: float
    wheel_speeds_mps: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)  # FL, FR, RL, RR
    accel_pedal: float = 0.0
    brake_pedal: float = 0.0
    object_valid: bool = False
    object_range_m: float = 0.0
    object_range_rate_mps: float = 0.0  # negative = closing
    wheel_rx_t_s: float = NEVER_S
    driver_rx_t_s: float = NEVER_S
    object_rx_t_s: float = NEVER_S
    wheel_e2e_score: int = 0
    driver_e2e_score: int = 0
    object_e2e_score: int = 0
    object_lateral_m: float = 0.0  # the object's centre offset from our path, left positive
    #: receiver faults of each input as FaultFlag bits (RATE, SEQUENCE), from can_dbc.Receiver.rx_flags
    wheel_rx_flags: int = 0
    driver_rx_flags: int = 0
    object_rx_flags: int = 0
    #: the node's own findings as FaultFlag bits (CLOCK, AUTH, FOREIGN_OVERRIDE)
    node_flags: int = 0
    #: the planar inputs: the latest ``RadarTrack`` slots' tracks (:class:`can_dbc.planar.Track`, empty slots
    #: left out; empty: no planar track, the stopping region is not evaluated), ``EscDynamics``'s yaw rate
    #: (rad/s, left positive) and ``DriverInput``'s steering-wheel angle (rad, left positive)
    tracks: tuple[Track, ...] = ()
    yaw_rate_radps: float = 0.0
    steering_wheel_rad: float = 0.0


class Evasion(NamedTuple):
    """A held evasive lane change (:mod:`ecu.core.lane_change_tracking`): its lateral offset (m, left positive;
    0: the held path is an arc), its lead-in (m: where its S begins), and the distance (m), heading change (rad)
    and lateral offset (m) dead-reckoned since it was latched."""

    offset_m: float = 0.0
    lead_m: float = 0.0
    travel_m: float = 0.0
    heading_rad: float = 0.0
    lateral_m: float = 0.0


class CoreState(NamedTuple):
    """Everything carried from one cycle to the next. The start-up state is ``CoreState()``."""

    mode: Mode = Mode.FAULT
    speed_mps: float = 0.0
    speed_initialised: bool = False
    #: mean speed of the non-driven wheels last cycle (:func:`ecu.core.speed_estimate.free_wheel_mean_mps`).
    prev_free_wheel_mean_mps: float = 0.0
    prev_decel_request_mps2: float = 0.0
    #: cycles since braking was last commanded (driver pedal or our request); saturates.
    cycles_since_brake: int = CYCLES_MAX
    #: consecutive cycles with every input valid (saturates at the recovery count).
    valid_cycles: int = 0
    #: a contingency active when the fault began, held while faulted.
    held_contingency: bool = False
    gate_interventions: int = 0
    #: cycles since the driver's accelerator was last pressed (saturates; :mod:`ecu.core.plausibility`).
    cycles_since_drive: int = CYCLES_MAX
    #: how far the driven wheels have plausibly run ahead of the non-driven ones (m/s, wheelspin).
    traction_excess_mps: float = 0.0
    #: the ``adaptive`` strategy's estimate of the achievable deceleration (:mod:`ecu.core.decel_estimate`).
    decel: DecelEstimate = DecelEstimate()
    #: the radar track's confirmation (:mod:`ecu.core.track_confirmation`).
    track: TrackState = TrackState()
    #: the steering path the contingency holds (its curvature, 1/m; None: none) and the overlay last
    #: requested (rad) (:mod:`ecu.core.steering`)
    steer_curvature_1pm: float | None = None
    steer_request_rad: float = 0.0
    #: the held path's lane change, if it is one (:mod:`ecu.core.steering`)
    steer_evasion: Evasion = Evasion()
    #: cycles slow with something near the nominal path (:mod:`ecu.core.way_out`; 0 without a way-out rule)
    slow_cycles: int = 0
    #: turns given back at the narrowing ahead (:mod:`ecu.core.way_out`, backing off)
    way_out_backoffs: int = 0


class CoreOutputs(NamedTuple):
    """The cycle's decision, after the output gate (values inside their DBC ranges)."""

    mode: Mode
    override_active: bool
    throttle_limit_pct: float
    brake_decel_request_mps2: float
    fault_flags: int
    proximity: float
    stopping_distance_m: float
    speed_estimate_mps: float
    disjoint: bool
    gate_intervened: bool
    #: ``SteeringOverride``: the road-wheel angle overlay (rad, left positive) and whether it is requested
    steer_active: bool = False
    steer_request_rad: float = 0.0
    #: ``EcuRegionStatus``: the stopping region's report (None: not evaluated, no planar track)
    region: RegionReport | None = None


class RegionReport(NamedTuple):
    """What ``EcuRegionStatus`` carries of one cycle's region decision (:mod:`ecu.core.planar`)."""

    contingency: int
    proximity: float
    curvature_1pm: float
    clearance_m: float
    stopping_distance_m: float
