"""A fleet run directory read for the bird's-eye view: the scene, and every car's box, speed, ECU mode and
stopping region over time, all in the world frame.

The times are ``world.csv``'s (one row per ECU cycle); each car's box centre, heading and speed come from it.
Its ECU mode and stopping path come from its own ``<vehicle>/timeseries.csv`` (the row at or before each
time): the path as the ECU reports it (``region_*`` columns: its contingency, curvature and stopping
distance), drawn at each time as :func:`cosim.results.region_view.stopping_band` draws a one-car run's (a band
of the car's width from its front bumper along an arc of that curvature) from the car's box in the world, that
is its pose in its own frame moved by the car's frame (``fleet.json``, :mod:`cosim.fleet.scene_file`). A
report of ``NOT_EVALUATED`` or a missing value draws nothing. A car's collision is its ``events.json`` contact
point, moved into the world likewise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import ConfigError
from ..results.region_view import CONTINGENCY_NAMES
from ..results.run_view import collision_event, floats, read_columns
from .scene_file import FLEET_SCENE_FILE, FleetScene, SceneCar, read_fleet_scene

WORLD_FILE = "world.csv"
#: the columns of the ECU's last EcuRegionStatus in a time series (cosim.results.run_record)
REGION_COLUMNS = ("region_contingency", "region_curvature_1pm", "region_stopping_m")


@dataclass(frozen=True)
class CarTrack:
    """One car over the world's times: ``box`` (n, 3) its box centre and heading, ``speed_mps`` (n,), ``mode`` its
    ECU mode (DBC names; None: not recorded), ``paths`` (n, 2) the curvature (1/m) and length (m) of its reported
    stopping path (NaN: none to draw; None: not recorded), ``collision`` (t, x, y) of its contact (None: none)."""

    box: np.ndarray
    speed_mps: np.ndarray
    mode: tuple[str, ...] | None
    paths: np.ndarray | None
    collision: tuple[float, float, float] | None


@dataclass(frozen=True)
class FleetView:
    path: Path
    scene: FleetScene
    t_s: np.ndarray
    tracks: tuple[CarTrack, ...]


def is_fleet_dir(path: Path) -> bool:
    """Whether ``path`` is a fleet run directory (it has ``fleet.json``)."""
    return (Path(path) / FLEET_SCENE_FILE).is_file()


def _at_or_before(times: np.ndarray, t_s: np.ndarray) -> np.ndarray:
    """For each time of ``t_s``, the index of the last of ``times`` at or before it (0 before the first)."""
    return np.clip(np.searchsorted(times, t_s + 1e-9, side="right") - 1, 0, len(times) - 1)


def _paths(cols: dict[str, list[str]], rows: list[int]) -> np.ndarray | None:
    """The reported stopping path (curvature, length) at each of ``rows`` (module docstring)."""
    if not all(name in cols for name in REGION_COLUMNS):
        return None
    kind, curvature, stopping = (np.array(cols[name], dtype=float)[rows] for name in REGION_COLUMNS)
    named = np.array([math.isfinite(k) and CONTINGENCY_NAMES.get(int(k), "NOT_EVALUATED") != "NOT_EVALUATED"
                      for k in kind.tolist()], dtype=bool)
    drawn = named & np.isfinite(curvature) & np.isfinite(stopping)
    return np.where(drawn[:, None], np.column_stack([curvature, stopping]), np.nan)


def _track(run_dir: Path, car: SceneCar, world: dict[str, list[str]], t_s: np.ndarray) -> CarTrack:
    source = run_dir / WORLD_FILE
    box = np.column_stack([floats(world, f"{car.name}_{c}", source) for c in ("x_m", "y_m", "yaw_rad")])
    speed = floats(world, f"{car.name}_speed_mps", source)
    path = run_dir / car.name / "timeseries.csv"
    mode = paths = None
    if path.is_file() and (cols := read_columns(path)).get("time_s"):
        rows = _at_or_before(floats(cols, "time_s", path), t_s).tolist()
        mode = tuple(cols["ecu_mode"][i] for i in rows) if "ecu_mode" in cols else None
        paths = _paths(cols, rows)
    event = collision_event(run_dir, car.name)
    hit = None
    if event is not None and "x_m" in event and "y_m" in event:
        hit = (float(event["t_s"]), *car.frame.to_world(float(event["x_m"]), float(event["y_m"])))
    return CarTrack(box, speed, mode, paths, hit)


def load_fleet_view(run_dir: Path) -> FleetView:
    """The fleet run at ``run_dir`` (module docstring); a one-line :class:`ConfigError` when it is not one."""
    run_dir = Path(run_dir)
    if not is_fleet_dir(run_dir):
        raise ConfigError(f"{run_dir}: not a crd fleet run directory (expected {FLEET_SCENE_FILE} from crd fleet --out)")
    scene = read_fleet_scene(run_dir / FLEET_SCENE_FILE)
    if not (run_dir / WORLD_FILE).is_file():
        raise ConfigError(f"{run_dir}: no {WORLD_FILE} (the fleet run wrote none)")
    world = read_columns(run_dir / WORLD_FILE)
    t_s = floats(world, "time_s", run_dir / WORLD_FILE)
    if not len(t_s):
        raise ConfigError(f"{run_dir / WORLD_FILE}: no rows")
    return FleetView(run_dir, scene, t_s, tuple(_track(run_dir, car, world, t_s) for car in scene.cars))

