"""A 2-D forward radar: tracks of the objects in its field of view, delayed, noisy, and within a frame budget.

The radar is mounted on the ego at :class:`RadarMount` (from the ego's reference point, in its
axes: x forward, y left, ISO 8855) and sees a wedge of ``±field_of_view_deg/2`` about its bore
sight out to ``max_range_m``. :func:`radar_step` is called once per ECU cycle ``k`` with the true
scene of that cycle (a :class:`Scan`) and returns the new :class:`RadarState` and, on report
cycles (``k % period_cycles == 0``), the reported tracks. It is pure: the same scans and
parameters give the same tracks.

Per object, from the scan ``latency_cycles`` old (the latency in whole ECU cycles, as today's radar):

* **visible** when the point of its box nearest to the sensor is within ``max_range_m`` and the
  box's angular extent (the azimuths of its corners) overlaps the field of view;
* **position** ``(x, y)``: that nearest point in sensor axes (the radar ranges to the nearest
  reflection; today's ``ObjectRange`` is likewise the gap to the object's rear); **velocity**
  ``(vx, vy)``: the object's velocity over ground minus that of the sensor's mounting point
  (``v_ego + ω × r``), in sensor axes; with ``report_at`` set, the object is still seen from the sensor but
  reported from that point instead: its box's point nearest it, in its axes, the velocity relative to it (the
  rear corner radars report in the forward radar's frame, :mod:`cosim.world.corner_radar`);
* **noise**: zero-mean Gaussian on x, y, vx, vy with the given standard deviations, from a numpy
  generator seeded ``(seed, k_scan)``: four normal numbers per object in order of object id, then one
  uniform number per object, whether it is visible or not (so visibility never shifts the stream);
  the uniform one decides a dropout (probability ``dropout_probability``): the track is not reported
  that cycle;
* **existence** ``1 - (1 - existence_gain)^n``: ``n`` consecutive report cycles in which the object
  was visible (a track's confidence grows with its confirmations; 0.5, 0.75, 0.875, ... by
  default). A dropped report still counts (the tracker coasts); an object out of view resets it;
* **size class**: the object's class (:data:`cosim.world.targets.SIZE_CLASSES`), taken as
  classified correctly.

**Frame budget**: at most ``max_tracks`` tracks per report. When more are visible the radar reports
the most urgent first: ascending time to collision ``r / (-dr/dt)`` along the line of sight
(receding objects: infinite), then ascending range, then id. Production radars order their
object lists too: Continental's ARS 408 can sort its list by range or by radar cross-section
(``RadarCfg_SortIndex`` in its configuration frame, as public drivers and DBCs show). For
collision avoidance the range order is wrong in the case that matters: a fast car closing from
40 m is more urgent than a pedestrian standing beside the road at 15 m; time to collision
ranks it first, and range breaks the ties among the many objects that do not close at all.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .geometry import BodyMotion, Box
from .targets import SIZE_CLASSES


@dataclass(frozen=True, slots=True)
class RadarMount:
    """Where the radar sits on the ego: position (m) from its reference point in its axes, and yaw (rad)."""

    x_m: float = 0.0
    y_m: float = 0.0
    yaw_rad: float = 0.0


@dataclass(frozen=True, slots=True)
class Radar2DParams:
    """The sensor's parameters (see the module docstring)."""

    mount: RadarMount = RadarMount()
    field_of_view_deg: float = 90.0
    max_range_m: float = 200.0
    period_cycles: int = 5  # ObjectTrack's 50 ms at the 10 ms ECU cycle
    latency_cycles: int = 10
    max_tracks: int = 8
    noise_std: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)  # x_m, y_m, vx_mps, vy_mps
    dropout_probability: float = 0.0
    existence_gain: float = 0.5
    seed: int = 0
    #: where the tracks are reported from: position nearest to this point, in its axes, velocity relative to it
    #: (None: the sensor's mount; the corner radars report in the forward radar's frame, cosim.world.corner_radar)
    report_at: RadarMount | None = None

    def __post_init__(self) -> None:
        checks = {"field_of_view_deg": 0.0 < self.field_of_view_deg <= 360.0, "max_range_m": self.max_range_m > 0.0,
                  "period_cycles": self.period_cycles >= 1, "latency_cycles": self.latency_cycles >= 0,
                  "max_tracks": self.max_tracks >= 0, "noise_std": min(self.noise_std) >= 0.0,
                  "dropout_probability": 0.0 <= self.dropout_probability <= 1.0,
                  "existence_gain": 0.0 < self.existence_gain <= 1.0}
        bad = [name for name, ok in checks.items() if not ok]
        if bad:
            raise ValueError(f"radar: out of range: {', '.join(f'{n}={getattr(self, n)!r}' for n in bad)}")


class EgoPose(NamedTuple):
    """The ego's reference point (m), heading (rad), velocity over ground in world axes (m/s) and yaw rate."""

    x_m: float
    y_m: float
    yaw_rad: float
    vx_mps: float
    vy_mps: float
    yaw_rate_radps: float = 0.0


class ObjectTruth(NamedTuple):
    """One object as it really is: a stable id, its box, its motion and its size class."""

    id: int
    box: Box
    motion: BodyMotion
    size_class: str


class Scan(NamedTuple):
    """The true scene at ECU cycle ``k``."""

    k: int
    ego: EgoPose
    objects: tuple[ObjectTruth, ...]


class Track(NamedTuple):
    """One reported object, in sensor axes: nearest point (m), relative velocity (m/s), existence, size class."""

    id: int
    x_m: float
    y_m: float
    vx_mps: float
    vy_mps: float
    existence: float
    size_class: str

    @property
    def range_m(self) -> float:
        return math.hypot(self.x_m, self.y_m)

    @property
    def ttc_s(self) -> float:
        """Time to collision along the line of sight, ``r / (-dr/dt)``; inf when not closing."""
        r = self.range_m
        closing = -(self.x_m * self.vx_mps + self.y_m * self.vy_mps) / r if r > 0.0 else math.inf
        return r / closing if closing > 0.0 else math.inf


@dataclass(frozen=True, slots=True)
class RadarState:
    """The scans still to be reported (newest last) and each object's consecutive visible reports."""

    pending: tuple[Scan, ...] = ()
    confirmations: tuple[tuple[int, int], ...] = ()


def _sensor_pose(ego: EgoPose, mount: RadarMount) -> tuple[float, float, float, float, float]:
    """World position (m) and heading (rad) of the sensor and the velocity (m/s) of its mounting point."""
    c, s = math.cos(ego.yaw_rad), math.sin(ego.yaw_rad)
    rx, ry = c * mount.x_m - s * mount.y_m, s * mount.x_m + c * mount.y_m
    w = ego.yaw_rate_radps
    return ego.x_m + rx, ego.y_m + ry, ego.yaw_rad + mount.yaw_rad, ego.vx_mps - w * ry, ego.vy_mps + w * rx


def _nearest_point(box: Box, px: float, py: float) -> tuple[float, float]:
    """The point of ``box`` nearest to (px, py) (the point itself when inside)."""
    (ux, uy), (nx, ny) = box.axes()
    dx, dy = px - box.x_m, py - box.y_m
    a = min(max(dx * ux + dy * uy, -box.length_m / 2), box.length_m / 2)
    b = min(max(dx * nx + dy * ny, -box.width_m / 2), box.width_m / 2)
    return box.x_m + a * ux + b * nx, box.y_m + a * uy + b * ny


def _in_view(box: Box, sx: float, sy: float, heading: float, half_fov: float) -> bool:
    """Whether the box's angular extent seen from (sx, sy) overlaps ``heading ± half_fov``.

    The corners' azimuths relative to the centre's, wrapped to ±pi, give the extent (floats: four
    ``atan2`` calls are cheaper than building an array for them).
    """
    (ux, uy), (nx, ny) = box.axes()
    hl, hw = box.length_m / 2.0, box.width_m / 2.0
    cx, cy = box.x_m - sx, box.y_m - sy
    centre = math.atan2(cy, cx)
    rel = [(math.atan2(cy + a * hl * uy + b * hw * ny, cx + a * hl * ux + b * hw * nx) - centre + math.pi)
           % (2 * math.pi) - math.pi for a, b in ((1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0))]
    lo, hi = centre - heading + min(rel), centre - heading + max(rel)
    return any(lo + shift <= half_fov and hi + shift >= -half_fov for shift in (-2 * math.pi, 0.0, 2 * math.pi))


def _measure(scan: Scan, params: Radar2DParams) -> dict[int, tuple[Track, bool]]:
    """Every visible object's noisy track (existence still 0) and whether its report drops out: seen from the
    sensor, reported from ``params.report_at`` (the sensor itself when None)."""
    sx, sy, heading, _, _ = _sensor_pose(scan.ego, params.mount)
    rx, ry, report_heading, svx, svy = _sensor_pose(scan.ego, params.report_at or params.mount)
    c, s = math.cos(report_heading), math.sin(report_heading)
    objects = sorted(scan.objects, key=lambda o: o.id)
    noise, drops = _draws(params, scan.k, len(objects))
    half_fov = math.radians(params.field_of_view_deg) / 2.0
    seen: dict[int, tuple[Track, bool]] = {}
    for obj, n, draw in zip(objects, noise, drops):
        px, py = _nearest_point(obj.box, sx, sy)
        if math.hypot(px - sx, py - sy) > params.max_range_m or not _in_view(obj.box, sx, sy, heading, half_fov):
            continue
        if params.report_at is not None:
            px, py = _nearest_point(obj.box, rx, ry)
        dx, dy = px - rx, py - ry
        vx, vy = obj.motion.vx_mps - svx, obj.motion.vy_mps - svy
        track = Track(obj.id, c * dx + s * dy + n[0], -s * dx + c * dy + n[1], c * vx + s * vy + n[2],
                      -s * vx + c * vy + n[3], 0.0, obj.size_class if obj.size_class in SIZE_CLASSES else "unknown")
        seen[obj.id] = (track, draw < params.dropout_probability)
    return seen


def _draws(params: Radar2DParams, k: int, n: int) -> tuple[list, list]:
    """Per object the four noise values and the dropout draw of scan ``k`` (module docstring). A radar without
    noise and dropouts draws nothing: zeros and a draw of 1 give the same tracks, without a generator per scan."""
    if not any(params.noise_std) and params.dropout_probability == 0.0:
        return [[0.0, 0.0, 0.0, 0.0]] * n, [1.0] * n
    rng = np.random.default_rng((params.seed, k))
    return (rng.standard_normal((n, 4)) * params.noise_std).tolist(), rng.random(n).tolist()


def _priority(track: Track) -> tuple[float, float, int]:
    return track.ttc_s, track.range_m, track.id


def radar_step(state: RadarState, scan: Scan, params: Radar2DParams) -> tuple[RadarState, tuple[Track, ...] | None]:
    """Record this cycle's scan; on a report cycle, the tracks of the scan ``latency_cycles`` old (None otherwise,
    and an empty tuple while no scan is old enough). Call it every ECU cycle, with ``k`` counting up by one."""
    pending = (*state.pending, scan)[-(params.latency_cycles + 1):]
    if scan.k % params.period_cycles:
        return RadarState(pending, state.confirmations), None
    if pending[0].k > scan.k - params.latency_cycles:
        return RadarState(pending, state.confirmations), ()
    seen = _measure(pending[0], params)
    before = dict(state.confirmations)
    counts = {i: before.get(i, 0) + 1 for i in seen}
    keep = 1.0 - params.existence_gain
    tracks = [t._replace(existence=1.0 - keep ** counts[i]) for i, (t, dropped) in seen.items() if not dropped]
    tracks.sort(key=_priority)
    return RadarState(pending, tuple(sorted(counts.items()))), tuple(tracks[:params.max_tracks])
