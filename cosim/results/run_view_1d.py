"""Today's 1-D runs in the bird's-eye view: the path as a straight road, the objects replayed.

A run of the 1-D world has no ``scene.json`` and no pose columns. Its view is made from what
it does have (see ``docs/run-format.md``):

* the ego moves along x: pose point ``x = position_m``, ``y = 0``, ``yaw = 0``; its box is the
  plant's ``length_m`` by ``width_m`` with the front bumper ``front_bumper_offset_m`` ahead of
  the pose point (``[plant]`` of ``config.resolved.toml``);
* the road is straight and has two 3.5 m lanes: the ego's, centred on ``y = 0`` (the scene's
  lane corridor, :data:`cosim.world.scene.LANE_HALF_WIDTH_M`), and one to its left;
* the objects (``[object]`` / ``[[objects]]``) are replayed with the run's own scene model
  (:class:`cosim.world.scene.Scene`): at every row its gap triggers see the ego's front bumper as
  the loop did, so braking and lateral motion start where they started in the run (to the
  time series' 6 significant digits);
* the ECU's stopping distance is ``EcuStatus.StoppingDistance`` from the strategy's ``can.blf``
  (every 100 ms), held until the next report, when the time series has no
  ``stopping_distance_m`` column.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..scenarios.loader import load_scenario
from ..world.reference_line import Line, PlanView
from ..world.road import LaneSection, Road
from ..world.ego import EgoBody
from ..world.plant_fmu import PlantPose
from ..world.scene import LANE_HALF_WIDTH_M, Scene
from ..world.scene_build import build_objects
from .run_view import (
    RunView, StrategyTrack, collision_event, floats, read_columns, with_collision,
)
from .scene_file import Body

_ROAD_MARGIN_M = 30.0


def straight_road(x0_m: float, x1_m: float) -> Road:
    """Two lanes along x over [x0, x1]: the reference line on the ego lane's left border, as OpenDRIVE draws it."""
    plan = PlanView.chained([Line(max(x1_m - x0_m, 1.0))], x0_m, LANE_HALF_WIDTH_M, 0.0)
    lane = 2.0 * LANE_HALF_WIDTH_M
    return Road(plan, (LaneSection.uniform(0.0, left_m=(lane,), right_m=(lane,)),))


def _object_poses(scenario, t_s: np.ndarray, position_m: np.ndarray) -> np.ndarray:
    """The objects' box centres over time (k, n, 3), replayed with the run's scene model."""
    body = EgoBody(scenario.plant)
    scene = Scene(build_objects(scenario, None), body, scenario.radar, scenario.end)
    poses = np.zeros((len(scene.objects), len(t_s), 3))
    for j, (t, x) in enumerate(zip(t_s.tolist(), position_m.tolist())):
        scene.observe(t, body.at(PlantPose(x, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)))
        for i, (obj, st) in enumerate(zip(scene.objects, scene.states(t))):
            poses[i, j, 0], poses[i, j, 1] = obj.centre(st)
            poses[i, j, 2] = st.yaw_rad
    return poses


def _stopping_from_can_log(log: Path, start_s: float, t_s: np.ndarray) -> np.ndarray | None:
    """``EcuStatus.StoppingDistance`` at each time of ``t_s`` (the last report at or before it; NaN before the first)."""
    if not log.is_file():
        return None
    import can

    from can_dbc import DATABASE

    status = DATABASE.get_message_by_name("EcuStatus")
    times, values = [], []
    with can.BLFReader(str(log)) as reader:
        for msg in reader:
            if msg.arbitration_id == status.frame_id and not msg.is_extended_id:
                times.append(msg.timestamp - start_s)
                values.append(status.decode(bytes(msg.data))["StoppingDistance"])
    if not times:
        return None
    # the log's stamps are the start time plus the simulation time: rounded to 1 us, the epoch's rounding is gone
    i = np.searchsorted(np.round(np.array(times), 6), t_s + 1e-9, side="right") - 1
    return np.where(i >= 0, np.array(values, dtype=float)[np.clip(i, 0, None)], np.nan)


def load_line_run(run_dir: Path, strategies: list[str], impacts: dict[str, float | None]) -> RunView:
    """The view of a 1-D run (see the module docstring)."""
    scenario = load_scenario(run_dir / "config.resolved.toml")
    plant = scenario.plant
    ego = Body("ego", "ego", plant.length_m, plant.width_m, plant.front_bumper_offset_m)
    objects = tuple(Body(o.name, "object", o.length_m, o.width_m, o.length_m / 2.0) for o in scenario.scene_objects())
    start_s = scenario.scenario.start_datetime.timestamp()
    tracks, x_lo, x_hi = {}, math.inf, -math.inf
    for strategy in strategies:
        path = run_dir / strategy / "timeseries.csv"
        cols = read_columns(path)
        t_s, x = floats(cols, "time_s", path), floats(cols, "position_m", path)
        objs = _object_poses(scenario, t_s, x)
        stopping = floats(cols, "stopping_distance_m", path) if "stopping_distance_m" in cols else \
            _stopping_from_can_log(run_dir / strategy / "can.blf", start_s, t_s)
        track = StrategyTrack(strategy, t_s, np.column_stack([x, np.zeros_like(x), np.zeros_like(x)]),
                              floats(cols, "speed_mps", path), objs,
                              tuple(cols["ecu_mode"]) if "ecu_mode" in cols else None, stopping, None, None)
        tracks[strategy] = with_collision(track, ego, objects, collision_event(run_dir, strategy), impacts.get(strategy))
        ends = [x.min() - plant.length_m, x.max() + plant.front_bumper_offset_m]
        ends += [float(objs[..., 0].min()), float(objs[..., 0].max())] if len(objects) else []
        x_lo, x_hi = min(x_lo, *ends), max(x_hi, *ends)
    road = straight_road(x_lo - _ROAD_MARGIN_M, x_hi + _ROAD_MARGIN_M)
    return RunView(run_dir, road, ego, objects, tracks)
