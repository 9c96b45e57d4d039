"""Plausibility of the inputs against each other and against physics (issue 15).

Each check yields one ``FaultFlag`` (``EcuStatus.Fault<Name>``), a pure
function of this cycle's inputs, the state, the speed estimate and the
parameters: :func:`input_health` makes those that need no speed estimate
(``WHEEL_SLIP``, ``PEDALS``, ``CLOCK``), :func:`speed_radar_implausible` the
one that does.

* ``WHEEL_SLIP``: wheel speeds that no road and no torque explain. While not
  braking the non-driven wheels roll at the car's speed, so they agree with
  each other, and the driven wheels agree with them except for traction slip::

      max(free) - min(free)      <= bound,  bound = wheel_slip_abs_mps + wheel_slip_fraction * max(free)
      min(free) - min(driven)    <= bound   (a driven wheel does not run slower: no brake acts)
      max(driven) - max(free)    <= max(bound, e[k-1] + g * dt)

  where ``e`` is the driven wheels' plausible lead (carried in the state) and
  ``g = driven_wheel_spinup_max_mps2`` while the accelerator is pressed or was
  within ``drive_memory_s`` (the powertrain's lag), else 0: drive torque may
  spin the driven axle up at most as fast as the engine's whole force can
  accelerate the wheels' inertia, and without it a spinning wheel only slows
  down. This is how production traction control tells wheelspin from a car
  that is going faster: the driven axle may run ahead of the free-rolling one
  while torque is applied, and the vehicle reference speed comes from the
  non-driven wheels (van Zanten et al., "VDC, the Vehicle Dynamics Control
  System of Bosch", SAE 950759, 1995; Bosch *Automotive Handbook*, TCS: both
  cited from memory, unconfirmed here). A failing check keeps ``e``: a lead
  forged in one step stays flagged until it shrinks. Before issue 25 the check
  was ``max(w) - min(w) <= bound`` on all four wheels, and full throttle on
  friction 0.3 spun the front wheels past it every 0.5 s (FAULT, throttle cut,
  STANDBY, 22 times in the paper run). Measured in the paper scenario without
  braking: non-driven spread 0, driven lag within 1.53 m/s; the bound (2 m/s +
  30 %) leaves twice that. While braking (commanded within ``brake_memory_s``,
  or the non-driven wheels slowing) ABS lets a wheel run far below the car, so
  nothing is checked. Known limit: a forger who lowers the non-driven wheels
  while the accelerator is pressed, no faster than a wheel could spin up, is
  not caught here; the speed estimate then follows the forgery at most at its
  slope limit, and ``SPEED_RADAR`` bounds it for an object in our path.
* ``SPEED_RADAR``: for a stationary object the closing speed ``-range_rate``
  equals our own speed; an object moving away closes slower. So a valid
  track closing faster than ``speed + radar_speed_tolerance_mps`` means our
  speed is wrong (forged or failed wheel speeds) or the object is oncoming
  in our path; the radar's closing speed is then the one the stopping path
  must use (:mod:`ecu.core.degraded`). One object cannot tell the two apart:
  the radar measures only relative speed. The ground can: every standing
  object closes at our true speed, so with planar tracks (issue 23) a
  **standing reference**, another track closing at our speed estimate within
  the same tolerance (``|vx + speed| <= tolerance``, :func:`ground_confirms`),
  shows that the wheels agree with the radar, and the object in our path that
  closes faster moves toward us: oncoming traffic, not a sensor fault (``crd
  fleet narrow_passage``: each car read the other, oncoming in the one lane
  between parked cars, as a fault and stopped in the passage). Wheels that
  read wrong by more than the tolerance are still caught: the standing
  objects then close at the true speed, not at the estimate, and confirm
  nothing; without planar tracks or without a standing object in view the
  check is the one before (the 1-D world is unchanged). Known limit: a track
  moving our way at just the forger's offset looks like a standing reference.
  Measured in the paper scenario, the
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

import math
from typing import NamedTuple

from .params import DRIVEN_WHEELS, NON_DRIVEN_WHEELS, CoreParams
from .relevance import nearest_track
from .speed_estimate import wheels_braked
from .types import CYCLES_MAX, RECEIVER_FLAGS, CoreInputs, CoreState, FaultFlag
from .validity import AGE_TOLERANCE_S


_WHEEL_SLIP, _PEDALS, _CLOCK = (1 << FaultFlag[name] for name in ("WHEEL_SLIP", "PEDALS", "CLOCK"))


class Health(NamedTuple):
    """What :func:`input_health` finds: the flags, which inputs may be used, and the state it carries."""

    flags: int
    wheels_ok: bool
    driver_ok: bool
    cycles_since_drive: int
    traction_excess_mps: float


def ground_confirms(speed_mps: float, inputs: CoreInputs, params: CoreParams) -> bool:
    """A planar track other than the one in our path closes at our speed estimate within the tolerance: a
    standing reference that the wheels agree with the radar (module doc)."""
    tol = params.radar_speed_tolerance_mps
    own = nearest_track(inputs.tracks, inputs, params) if inputs.object_valid else None
    return any(i != own and abs(t.vx_mps + speed_mps) <= tol for i, t in enumerate(inputs.tracks))


def speed_radar_implausible(speed_mps: float, inputs: CoreInputs, relevant: bool, params: CoreParams) -> bool:
    """A ``relevant`` object (valid and in our path, :mod:`ecu.core.relevance`) closes faster than our
    speed estimate plus the tolerance (out-of-path objects, e.g. oncoming traffic in the next lane,
    are not compared), and no standing reference confirms our speed (:func:`ground_confirms`)."""
    return relevant and -inputs.object_range_rate_mps > speed_mps + params.radar_speed_tolerance_mps \
        and not ground_confirms(speed_mps, inputs, params)


def wheel_spread(state: CoreState, wheels: tuple[float, ...], braking: bool, driving: bool,
                 params: CoreParams) -> tuple[bool, float]:
    """(``WHEEL_SLIP``: the wheels' spread is one that no road and no torque explain; the driven wheels'
    plausible lead over the non-driven ones to carry, m/s). The bounds are those of the module doc."""
    free = tuple(map(wheels.__getitem__, NON_DRIVEN_WHEELS[params.driven_axle]))
    driven = tuple(map(wheels.__getitem__, DRIVEN_WHEELS[params.driven_axle])) or free
    top = max(free)
    bound = params.wheel_slip_abs_mps + params.wheel_slip_fraction * top
    lead = max(driven) - top
    growth = params.driven_wheel_spinup_max_mps2 * params.cycle_s if driving else 0.0
    allowed = max(bound, state.traction_excess_mps + growth)
    implausible = not braking and (top - min(free) > bound or min(free) - min(driven) > bound or lead > allowed)
    if implausible or not math.isfinite(lead):
        return implausible, state.traction_excess_mps
    return False, min(allowed, max(0.0, lead))


def input_health(state: CoreState, inputs: CoreInputs, params: CoreParams) -> Health:
    """The fault flags of the receiver, the node and the checks that need no speed estimate; whether the
    wheel speeds and the driver input may be used; the state they carry. Checks: the module doc."""
    flags = inputs.wheel_rx_flags | inputs.driver_rx_flags | inputs.object_rx_flags | inputs.node_flags
    since_drive = 0 if inputs.accel_pedal > 0.0 else min(state.cycles_since_drive + 1, CYCLES_MAX)
    driving = since_drive * params.cycle_s < params.drive_memory_s
    slip, lead = wheel_spread(state, inputs.wheel_speeds_mps, wheels_braked(state, inputs, params), driving,
                             params)
    if slip:
        flags |= _WHEEL_SLIP
    limit = params.pedal_conflict_fraction
    pedals = inputs.accel_pedal > limit and inputs.brake_pedal > limit
    if pedals:
        flags |= _PEDALS
    late = inputs.t_s + AGE_TOLERANCE_S  # stamped after this cycle: the clock went backwards
    if inputs.wheel_rx_t_s > late or inputs.driver_rx_t_s > late or inputs.object_rx_t_s > late:
        flags |= _CLOCK
    return Health(flags, not (slip or inputs.wheel_rx_flags & RECEIVER_FLAGS),
                  not (pedals or inputs.driver_rx_flags & RECEIVER_FLAGS), since_drive, lead)
