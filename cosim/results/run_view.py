"""A run directory read for the bird's-eye view: the scene, and per strategy the poses over time.

The inputs are documented in ``docs/run-format.md``. A planar run has ``scene.json`` and the
pose columns (``x_m``, ``y_m``, ``yaw_rad``, ``obj<i>_x_m`` ...) in each ``timeseries.csv``; a run
of today's 1-D world has neither and is read through :mod:`cosim.results.run_view_1d` (the ego
on a straight road, the objects replayed from ``config.resolved.toml``). Both give a
:class:`RunView`.
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import ConfigError
from ..world.geometry import Box, contact
from ..world.road import Road
from .region_view import regions_from_columns
from .scene_file import Body, read_scene

SCENE_FILE = "scene.json"
STOPPING_REGION_FILE = "stopping_region.json"


@dataclass(frozen=True)
class Collision:
    """Where a run hit an object: time (s), contact point (m), normal (from the ego), object index, impact speed."""

    t_s: float
    x_m: float
    y_m: float
    normal: tuple[float, float]
    object_index: int | None
    impact_speed_mps: float | None


@dataclass(frozen=True)
class StrategyTrack:
    """One strategy's run: per time step the ego's pose point and speed, the objects' box centres, the ECU's view.

    ``ego`` has shape (n, 3) (x_m, y_m, yaw_rad); ``objects`` (k, n, 3); ``stopping_m`` the ECU's stopping
    distance (NaN where not reported); ``regions`` the stopping region polygons (their start times and
    vertex arrays) when the run reports them.
    """

    strategy: str
    t_s: np.ndarray
    ego: np.ndarray
    speed_mps: np.ndarray
    objects: np.ndarray
    mode: tuple[str, ...] | None
    stopping_m: np.ndarray | None
    regions: tuple[np.ndarray, tuple[np.ndarray, ...]] | None
    collision: Collision | None
    #: per region polygon, its label (the ECU's contingency, :mod:`cosim.results.region_view`); None: unlabelled
    region_labels: tuple[str, ...] | None = None


@dataclass(frozen=True)
class RunView:
    path: Path
    road: Road | None
    ego: Body
    objects: tuple[Body, ...]
    tracks: dict[str, StrategyTrack]


def body_box(body: Body, x_m: float, y_m: float, yaw_rad: float) -> Box:
    """The box of ``body`` whose pose point is at (x, y) with heading ``yaw_rad``."""
    shift = body.front_m - body.length_m / 2.0
    return Box(x_m + shift * math.cos(yaw_rad), y_m + shift * math.sin(yaw_rad), yaw_rad, body.length_m, body.width_m)


def read_columns(path: Path) -> dict[str, list[str]]:
    """A CSV file's columns by header name (as text)."""
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    if not rows:
        raise ConfigError(f"{path}: empty (expected a header row)")
    header, body = rows[0], rows[1:]
    return {name: [r[i] for r in body] for i, name in enumerate(header)}


def floats(columns: dict[str, list[str]], name: str, source: Path) -> np.ndarray:
    if name not in columns:
        raise ConfigError(f"{source}: missing column {name!r}")
    return np.array(columns[name], dtype=float)


def metrics_runs(run_dir: Path) -> list[dict]:
    """The ``runs`` of ``metrics.json``; a ConfigError when the directory is not a run's."""
    metrics = run_dir / "metrics.json"
    if not metrics.is_file():
        raise ConfigError(f"{run_dir}: not a crd run directory (expected {metrics.name} from crd run/paper --out, "
                          "or fleet.json from crd fleet --out)")
    runs = json.loads(metrics.read_text()).get("runs")
    if not isinstance(runs, list):
        raise ConfigError(f"{run_dir}: not a crd run directory ({metrics.name} has no runs; a crd fleet directory "
                          "has fleet.json: run crd fleet again)")
    return runs


def collision_event(run_dir: Path, strategy: str) -> dict | None:
    """The ``collision`` event of a strategy's ``events.json`` (None: none)."""
    events = run_dir / strategy / "events.json"
    if not events.is_file():
        return None
    return next((e for e in json.loads(events.read_text())["events"] if e.get("kind") == "collision"), None)


def _regions(path: Path) -> tuple[np.ndarray, tuple[np.ndarray, ...]] | None:
    if not path.is_file():
        return None
    data = json.loads(path.read_text())
    times, polygons = data.get("t_s"), data.get("polygons")
    if not isinstance(times, list) or not isinstance(polygons, list) or len(times) != len(polygons):
        raise ConfigError(f"{path}: expected lists t_s and polygons of the same length")
    return np.array(times, dtype=float), tuple(np.array(p, dtype=float).reshape(-1, 2) for p in polygons)


def find_collision(view_ego: Body, objects: tuple[Body, ...], track: StrategyTrack, event: dict | None,
                   impact: float | None) -> Collision | None:
    """The contact at the collision event: the event's own point when it has one (``x_m``, ``y_m``, ``normal``),
    else the contact of the boxes at the last sample, moved on at their speeds to the event's time."""
    if event is None:
        return None
    t_c = float(event["t_s"])
    if "x_m" in event and "y_m" in event:
        normal = tuple(event.get("normal", (1.0, 0.0)))
        return Collision(t_c, float(event["x_m"]), float(event["y_m"]), normal, event.get("object"), impact)
    dt = max(0.0, t_c - float(track.t_s[-1]))
    ego = body_box(view_ego, *_moved_on(track.ego, track.t_s, dt, track.speed_mps[-1]))
    best = None
    for i, body in enumerate(objects):
        hit = contact(ego, body_box(body, *_moved_on(track.objects[i], track.t_s, dt)), tol_m=0.05)
        if hit is not None and (best is None or hit.depth_m > best[1].depth_m):
            best = (i, hit)
    if best is None:  # nothing within 5 cm: mark the ego's front
        front = ego.corners()[[0, 3]].mean(axis=0)
        return Collision(t_c, float(front[0]), float(front[1]), (math.cos(ego.yaw_rad), math.sin(ego.yaw_rad)),
                         None, impact)
    i, hit = best
    return Collision(t_c, hit.x_m, hit.y_m, (hit.normal_x, hit.normal_y), i, impact)


def _moved_on(poses: np.ndarray, t_s: np.ndarray, dt: float, speed_mps: float | None = None) -> tuple[float, float, float]:
    """The last pose moved on by ``dt`` at ``speed_mps`` along its heading, or (None) at the velocity of its last step."""
    x, y, yaw = (float(v) for v in poses[-1])
    if speed_mps is not None:
        return x + speed_mps * dt * math.cos(yaw), y + speed_mps * dt * math.sin(yaw), yaw
    if len(t_s) < 2 or t_s[-1] <= t_s[-2]:
        return x, y, yaw
    f = dt / float(t_s[-1] - t_s[-2])
    return x + f * (x - poses[-2, 0]), y + f * (y - poses[-2, 1]), yaw


def load_run_view(run_dir: Path, strategies: list[str] | None = None) -> RunView:
    """The run at ``run_dir`` for the given strategies (default: every one with a time series)."""
    run_dir = Path(run_dir)
    runs = metrics_runs(run_dir)
    names = [r["strategy"] for r in runs if (run_dir / r["strategy"] / "timeseries.csv").is_file()]
    if strategies:
        missing = [s for s in strategies if s not in names]
        if missing:
            raise ConfigError(f"{run_dir}: no time series for strategy {missing[0]!r} (have {names})")
        names = strategies
    if not names:
        raise ConfigError(f"{run_dir}: no strategy has a timeseries.csv")
    impacts = {r["strategy"]: r.get("impact_speed_mps") for r in runs}
    if (run_dir / SCENE_FILE).is_file():
        scene = read_scene(run_dir / SCENE_FILE)
        tracks = {s: _planar_track(run_dir, s, scene.ego, scene.objects, impacts.get(s)) for s in names}
        return RunView(run_dir, scene.road, scene.ego, scene.objects, tracks)
    from .run_view_1d import load_line_run  # today's runs: the scene comes from config.resolved.toml

    return load_line_run(run_dir, names, impacts)


def _planar_track(run_dir: Path, strategy: str, ego: Body, objects: tuple[Body, ...],
                  impact: float | None) -> StrategyTrack:
    path = run_dir / strategy / "timeseries.csv"
    cols = read_columns(path)
    pose = np.column_stack([floats(cols, c, path) for c in ("x_m", "y_m", "yaw_rad")])
    objs = np.stack([np.column_stack([floats(cols, f"obj{i}_{c}", path) for c in ("x_m", "y_m", "yaw_rad")])
                     for i in range(len(objects))]) if objects else np.empty((0, len(pose), 3))
    t_s = floats(cols, "time_s", path)
    regions, labels = _regions(run_dir / strategy / STOPPING_REGION_FILE), None
    if regions is None and (reported := regions_from_columns(cols, t_s, pose, ego)) is not None:
        regions, labels = reported[:2], reported[2]
    track = StrategyTrack(strategy, t_s, pose, floats(cols, "speed_mps", path), objs,
                          tuple(cols["ecu_mode"]) if "ecu_mode" in cols else None,
                          floats(cols, "stopping_distance_m", path) if "stopping_distance_m" in cols else None,
                          regions, None, labels)
    return with_collision(track, ego, objects, collision_event(run_dir, strategy), impact)


def with_collision(track: StrategyTrack, ego: Body, objects: tuple[Body, ...], event: dict | None,
                   impact: float | None) -> StrategyTrack:
    return replace(track, collision=find_collision(ego, objects, track, event, impact))
