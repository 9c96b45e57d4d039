"""What the first half of a closed loop's cycle leaves for the second (:class:`cosim.loop.master.ClosedLoop`:
``cycle_out`` builds it, ``cycle_in`` reads it; a fleet runs every car's first half before any car's second)."""

from __future__ import annotations

from ..world.driver_models import Pedals
from ..world.ego import Ego
from ..world.plant_fmu import PlantSample


class Outgoing:
    """What the first half of a cycle leaves for the second. A plain slotted class, built once per cycle: 3.5x
    cheaper to build (0.26 instead of 0.96 µs, timeit on the loaded 2-core machine) than the frozen dataclass
    it replaces, whose ``__init__`` goes through ``object.__setattr__``; nothing mutates it."""

    __slots__ = ("sample", "ego", "pedals", "steering_rad", "gap_m", "frames")

    def __init__(self, sample: PlantSample, ego: Ego, pedals: Pedals, steering_rad: float, gap_m: float,
                 frames: list) -> None:
        self.sample, self.ego, self.pedals, self.steering_rad = sample, ego, pedals, steering_rad
        self.gap_m, self.frames = gap_m, frames
