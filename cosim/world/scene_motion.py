"""Motion of one scene object: closed-form longitudinal and lateral profiles.

Positions are functions of time and of the trigger times (when braking and
lateral motion began), so the object can be evaluated at any plant step
without integrating: the run stays deterministic whatever the step pattern.

Longitudinal (rear position ``x``, speed ``v``; braking starts at ``t_b``,
``tau = t - t_b``, deceleration ``D`` reached linearly within ``R`` s, down
to ``v_end``)::

    ramp (tau <= R):   v = v0 - D tau^2 / (2R),    x = x_b + v0 tau - D tau^3 / (6R)
    then:              v = v_R - D (tau - R),      x = x_R + v_R (tau - R) - D (tau - R)^2 / 2
    after v = v_end:   v = v_end,                  x grows at v_end

with ``v_R = v0 - D R / 2`` and ``x_R`` the ramp's end. Euro NCAP CCRb:
``D`` = 4 m/s^2 reached within 1.0 s (Euro NCAP 2026 Crash Avoidance -
Frontal Collisions v1.1, CCRb). ``R = 0`` is a step in deceleration.

Lateral (centre offset ``y``, left positive; motion starts at ``t_l``): ``y``
moves at constant ``lateral_speed_mps`` from ``lateral_m`` to
``lateral_end_m`` and stays there (cut-in, cut-out).

In the plane (:class:`cosim.world.scene_objects.PathMotion`) the two profiles run in the object's own
frame: along its heading and across it, from where it was placed. Placed on
the path (heading 0, no pose) that frame is the world's and the profiles are
used as they are, with no arithmetic in between: the 1-D world bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

from ..scenarios.config import ObjectConfig


@dataclass(frozen=True, slots=True)
class Longitudinal:
    """Constant speed, or braking at ``decel_mps2`` (ramp ``ramp_s``) down to ``end_speed_mps``."""

    rear0_m: float
    speed_mps: float
    decel_mps2: float = 0.0
    ramp_s: float = 0.0
    end_speed_mps: float = 0.0

    def _stop_tau_s(self) -> float:
        """Time after the brake onset at which the speed reaches ``end_speed_mps`` (s)."""
        dv = self.speed_mps - self.end_speed_mps
        d, r = self.decel_mps2, self.ramp_s
        if dv <= 0.0 or d <= 0.0:
            return 0.0
        if r > 0.0 and dv <= d * r / 2.0:
            return math.sqrt(2.0 * r * dv / d)
        return r + (dv - d * r / 2.0) / d

    def _braking(self, tau: float) -> tuple[float, float]:
        """(distance since the onset (m), speed (m/s)) ``tau`` s into an unfinished braking."""
        v0, d, r = self.speed_mps, self.decel_mps2, self.ramp_s
        if tau <= r:
            return v0 * tau - d * tau**3 / (6.0 * r), v0 - d * tau * tau / (2.0 * r)
        x_r, v_r = v0 * r - d * r * r / 6.0, v0 - d * r / 2.0
        u = tau - r
        return x_r + v_r * u - d * u * u / 2.0, v_r - d * u

    def state(self, t_s: float, brake_t_s: float | None) -> tuple[float, float]:
        """(rear position (m), speed (m/s)) at ``t_s`` with braking from ``brake_t_s`` (None: never)."""
        if brake_t_s is None or t_s <= brake_t_s or self.decel_mps2 <= 0.0:
            return self.rear0_m + self.speed_mps * t_s, self.speed_mps
        x_b = self.rear0_m + self.speed_mps * brake_t_s
        tau = t_s - brake_t_s
        tau_e = self._stop_tau_s()
        if tau <= tau_e:
            dx, v = self._braking(tau)
            return x_b + dx, v
        dx, _ = self._braking(tau_e)
        return x_b + dx + self.end_speed_mps * (tau - tau_e), self.end_speed_mps


@dataclass(frozen=True, slots=True)
class Lateral:
    """Centre offset ``y0_m``, moving at ``speed_mps`` toward ``end_m`` once started."""

    y0_m: float
    speed_mps: float = 0.0
    end_m: float | None = None

    def state(self, t_s: float, start_t_s: float | None) -> tuple[float, float]:
        """(centre offset (m), lateral speed (m/s)) at ``t_s`` with the motion from ``start_t_s``."""
        if self.end_m is None or start_t_s is None or t_s <= start_t_s or self.speed_mps <= 0.0:
            return self.y0_m, 0.0
        span = self.end_m - self.y0_m
        moved = self.speed_mps * (t_s - start_t_s)
        if moved >= abs(span):
            return self.end_m, 0.0
        sign = 1.0 if span > 0.0 else -1.0
        return self.y0_m + sign * moved, sign * self.speed_mps


def motions(cfg: ObjectConfig, rear0_m: float | None = None, y0_m: float | None = None) -> tuple[Longitudinal, Lateral]:
    """The two profiles of one configured object (from ``rear0_m``, ``y0_m``: default ``position_m``, ``lateral_m``)."""
    end_speed = min(cfg.brake_to_speed_mps, max(cfg.speed_mps, 0.0))
    rear0 = cfg.position_m if rear0_m is None else rear0_m
    lon = Longitudinal(rear0, cfg.speed_mps, cfg.brake_decel_mps2, cfg.brake_ramp_s, end_speed)
    if y0_m is None or cfg.lateral_end_m is None:
        return lon, Lateral(cfg.lateral_m if y0_m is None else y0_m, cfg.lateral_speed_mps, cfg.lateral_end_m)
    return lon, Lateral(y0_m, cfg.lateral_speed_mps, cfg.lateral_end_m - cfg.lateral_m + y0_m)


class BodyState(NamedTuple):
    """An object at one instant: its reference point (m), heading (rad, and its cos and sin), the reference point's velocity
    over ground in world axes (m/s), yaw rate (rad/s) and speed along its heading (m/s)."""

    x_m: float
    y_m: float
    yaw_rad: float
    cos_h: float
    sin_h: float
    vx_mps: float
    vy_mps: float
    yaw_rate_radps: float
    speed_mps: float
