"""The 2-D radar on the scene: every object it sees, as tracks, each radar cycle (:mod:`cosim.world.radar2d`).

The 1-D ECU gets one object (``ObjectTrack``, :meth:`cosim.world.scene.Scene.radar_truth` and
:class:`cosim.world.radar_model.RadarModel`). The planar contract will carry several tracks per
radar cycle; this feed makes them from the same scene and the same ``[radar]`` table, and the
loop hands them to its frame builder on the cycles ``ObjectTrack`` goes out
(:meth:`cosim.loop.master.ClosedLoop._frames_out`), newest in :attr:`TrackFeed.latest`.

Mapping of ``[radar]``: the field of view, range and latency (in whole ECU cycles) as they are; the
range noise on the track's x and y, the range-rate noise on its vx and vy; the dropout probability
per track; the seed of the scenario. The sensor sits at the front bumper's centre, looking ahead.
Only the scans a report will read (those ``latency`` cycles before a report cycle) carry the
objects; the others are recorded empty, which changes no track.
"""

from __future__ import annotations

from can_dbc import ECU_CYCLE_S

from ..scenarios.config import OBJECT_TRACK_PERIOD_S, RadarConfig
from .ego import Ego, EgoBody
from .radar2d import EgoPose, ObjectTruth, Radar2DParams, RadarMount, RadarState, Scan, Track, radar_step
from .scene import Scene
from .scene_contact import object_box, object_motion


def radar_params(cfg: RadarConfig, ego: EgoBody, seed: int) -> Radar2DParams:
    """``[radar]`` as the 2-D radar's parameters (module docstring)."""
    r, rr = cfg.range_noise_std_m, cfg.range_rate_noise_std_mps
    return Radar2DParams(mount=RadarMount(x_m=ego.front_m), field_of_view_deg=cfg.field_of_view_deg,
                         max_range_m=cfg.max_range_m, period_cycles=int(round(OBJECT_TRACK_PERIOD_S / ECU_CYCLE_S)),
                         latency_cycles=int(round(cfg.latency_s / ECU_CYCLE_S)), noise_std=(r, r, rr, rr),
                         dropout_probability=cfg.dropout_probability, seed=seed)


class TrackFeed:
    """Scans the scene every ECU cycle; returns the tracks on report cycles (None on the others)."""

    def __init__(self, scene: Scene, params: Radar2DParams) -> None:
        self.scene, self.params = scene, params
        self.state = RadarState()
        self.latest: tuple[Track, ...] = ()

    def step(self, cycle: int, t_s: float, ego: Ego) -> tuple[Track, ...] | None:
        """The tracks of this cycle (``cycle`` counts ECU cycles from 0; call it on every one)."""
        return self.report(self.scan(cycle, t_s, ego))

    def scan(self, cycle: int, t_s: float, ego: Ego) -> Scan:
        """The scene as the sensor scans it this cycle: the objects only when a report will read the scan. Sensors
        of one period and latency share it (:mod:`cosim.world.corner_radar`: it is built once for them)."""
        pose = EgoPose(ego.x_m, ego.y_m, ego.yaw_rad, *self.scene.ego.velocity(ego), ego.yaw_rate_radps)
        truths = ()
        if (cycle + self.params.latency_cycles) % self.params.period_cycles == 0:  # a report will read this scan
            truths = tuple(ObjectTruth(obj.index, object_box(obj, st), object_motion(obj, st), obj.size_class)
                           for obj, st in zip(self.scene.objects, self.scene.states(t_s)))
        return Scan(cycle, pose, truths)

    def report(self, scan: Scan) -> tuple[Track, ...] | None:
        """This sensor's tracks from ``scan`` on report cycles (None on the others)."""
        self.state, tracks = radar_step(self.state, scan, self.params)
        if tracks is not None:
            self.latest = tracks
        return tracks
