"""Objects in the lane: stationary or at constant speed, with a length."""

from __future__ import annotations

from dataclasses import dataclass

from ..scenarios.config import ObjectConfig


@dataclass(frozen=True, slots=True)
class LaneObject:
    """An object whose rear is at ``rear_m + speed_mps * t`` on the path (m, m/s)."""

    rear_m: float
    speed_mps: float
    length_m: float
    lateral_m: float = 0.0

    @classmethod
    def from_config(cls, cfg: ObjectConfig) -> "LaneObject | None":
        if not cfg.enabled:
            return None
        return cls(cfg.position_m, cfg.speed_mps, cfg.length_m, cfg.lateral_m)

    def rear_at(self, t_s: float) -> float:
        """Position of the object's rear at ``t_s`` (m)."""
        return self.rear_m + self.speed_mps * t_s

    def gap_m(self, t_s: float, bumper_m: float) -> float:
        """Distance from the front bumper at ``bumper_m`` to the object's rear (m); < 0 means overlap."""
        return self.rear_at(t_s) - bumper_m
