"""Plausibility of the inputs against each other and against physics (issue 15).

Each check yields one ``FaultFlag`` (``EcuStatus.Fault<Name>``), a pure
function of this cycle's inputs, the state, the speed estimate and the
parameters: :func:`input_health` makes those that need no speed estimate
(``WHEEL_SLIP``, ``PEDALS``, ``CLOCK``), :func:`speed_radar_implausible` the
one that does.

* ``WHEEL_SLIP``: while not braking, the four wheels roll at the car's speed
  except for the driven wheels' traction slip, so
  ``max(w) - min(w) <= wheel_slip_abs_mps + wheel_slip_fraction * max(w)``.
  Measured in the paper scenario without braking: at most 1.53 m/s, and at
  most 8.5 % above 5 m/s; the bounds (2 m/s + 30 %) leave twice that. While
  braking (commanded within ``brake_memory_s``, or the mean wheel speed
  falling), ABS lets a wheel run far below the car, so nothing is checked.
* ``SPEED_RADAR``: for a stationary object the closing speed ``-range_rate``
  equals our own speed; an object moving away closes slower. So a valid
  track closing faster than ``speed + radar_speed_tolerance_mps`` means our
  speed is wrong (forged or failed wheel speeds) or an object oncoming in our
  lane; either way the radar's closing speed is the one the stopping path
  must use (:mod:`ecu.core.degraded`). Measured in the paper scenario, the
  closing speed exceeds the speed estimate by at most 3.3 m/s (3.9 m/s on a
  road of friction 0.6): under ABS the reference speed reads low and the
  radar lags 0.1 s; tolerance 6 m/s. A forger who lowers the wheel speeds by
  less than that is not caught by this check.
* ``PEDALS``: accelerator and brake both above ``pedal_conflict_fraction``
  (50 %): not a plausible driver command (brake-throttle override logic
  treats the brake as the intent); the driver input counts as invalid.
* ``CLOCK``: an input received *after* the cycle time (``rx_t_s > t_s``), i.e.
  the clock went backwards: ages would be negative and nothing would time out.
"""

from __future__ import annotations

from .params import CoreParams
from .types import RECEIVER_FLAGS, CoreInputs, CoreState, FaultFlag
from .validity import AGE_TOLERANCE_S


def speed_radar_implausible(speed_mps: float, inputs: CoreInputs, relevant: bool, params: CoreParams) -> bool:
    """A ``relevant`` object (valid and in our path, :mod:`ecu.core.relevance`) closes faster than our
    speed estimate plus the tolerance (out-of-path objects, e.g. oncoming traffic in the next lane,
    are not compared)."""
    return relevant and -inputs.object_range_rate_mps > speed_mps + params.radar_speed_tolerance_mps


def input_health(state: CoreState, inputs: CoreInputs, params: CoreParams) -> tuple[int, bool, bool]:
    """(fault flags of the receiver, the node and the checks that need no speed estimate; whether the
    wheel speeds and the driver input may be used). The checks are those of the module doc."""
    flags = inputs.wheel_rx_flags | inputs.driver_rx_flags | inputs.object_rx_flags | inputs.node_flags
    wheels = inputs.wheel_speeds_mps
    # braking as the speed estimate sees it: commanded within brake_memory_s, or the wheels slowing
    braking = (inputs.brake_pedal > 0.0 or state.prev_decel_request_mps2 > 0.0
               or (state.cycles_since_brake + 1) * params.cycle_s < params.brake_memory_s
               or (state.speed_initialised and sum(wheels) / 4.0 < state.prev_wheel_mean_mps))
    top = max(wheels)
    slip = not braking and top - min(wheels) > params.wheel_slip_abs_mps + params.wheel_slip_fraction * top
    if slip:
        flags |= 1 << FaultFlag.WHEEL_SLIP
    limit = params.pedal_conflict_fraction
    pedals = inputs.accel_pedal > limit and inputs.brake_pedal > limit
    if pedals:
        flags |= 1 << FaultFlag.PEDALS
    late = inputs.t_s + AGE_TOLERANCE_S  # stamped after this cycle: the clock went backwards
    if inputs.wheel_rx_t_s > late or inputs.driver_rx_t_s > late or inputs.object_rx_t_s > late:
        flags |= 1 << FaultFlag.CLOCK
    return (flags, not (slip or inputs.wheel_rx_flags & RECEIVER_FLAGS),
            not (pedals or inputs.driver_rx_flags & RECEIVER_FLAGS))
