"""What a planar cell's run adds to its :class:`~cosim.matrix.scoring.Outcome`: the object it touched, how far
it left the road, and a thinned trace of the poses for the report's bird's-eye thumbnail.

Road departure (UN R79 Rev.4, ESF: emergency steering must not lead the vehicle off the road) is the
largest distance (m) by which a corner of the ego's box got beyond the road's outer edge, sampled every
:data:`TRACE_EVERY` ECU cycles and at the last one (0: it never did). Beyond the road's two ends
nothing is measured (a turn into a side road that ``[road]`` does not hold is not a departure of it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..results.run_record import EGO_POSE_COLUMNS, OBJECT_POSE_COLUMNS
from ..scenarios.config import Scenario
from ..world.road import Road
from ..world.scene_build import build_road

#: the trace keeps one ECU cycle in this many (0.1 s), and the last one
TRACE_EVERY = 10


@dataclass(frozen=True)
class PlanarOutcome:
    """A planar run's additions (plain data: it crosses process boundaries)."""

    hit_object: str | None  #: the name of the object touched (None: no contact)
    road_departure_m: float  #: how far the ego's box got beyond the road's edge (0: never)
    trace: dict[str, Any]  #: thinned poses: t_s, ego [x, y, yaw], speed_mps, objects [[x, y, yaw]...], contact


def _rows(n: int) -> list[int]:
    keep = list(range(0, n, TRACE_EVERY))
    return keep + [n - 1] if n and keep[-1] != n - 1 else keep


def ego_corners(scenario: Scenario, pose: np.ndarray) -> np.ndarray:
    """The ego box's four corners for each pose point row [x, y, yaw]: shape (k, 4, 2)."""
    p = scenario.plant
    c, s = np.cos(pose[:, 2]), np.sin(pose[:, 2])
    shift = p.front_m - p.length_m / 2.0  # pose point -> box centre along the heading
    cx, cy = pose[:, 0] + shift * c, pose[:, 1] + shift * s
    out = []
    for a, b in ((0.5, 0.5), (0.5, -0.5), (-0.5, -0.5), (-0.5, 0.5)):
        lx, ly = a * p.length_m, b * p.width_m
        out.append(np.column_stack([cx + lx * c - ly * s, cy + lx * s + ly * c]))
    return np.stack(out, axis=1)


def departure_m(road: Road, corners: np.ndarray) -> float:
    """The largest distance (m) of a point of ``corners`` (…, 2) beyond the road's left or right edge."""
    worst = 0.0
    for x, y in corners.reshape(-1, 2):
        s, t = road.to_st(float(x), float(y))
        if not 0.0 <= s <= road.length_m:
            continue
        sec = road.section_at(s)
        borders = sec.borders_m(s - sec.s_m)
        left = float(borders[sec.left[-1].id][1]) if sec.left else 0.0
        right = float(borders[sec.right[-1].id][1]) if sec.right else 0.0
        worst = max(worst, t - left, right - t)
    return worst


def planar_outcome(record, scenario: Scenario) -> PlanarOutcome | None:
    """The additions of a planar run (None for a run of the 1-D world)."""
    if not scenario.planar or not record.rows or "x_m" not in record.columns:
        return None
    keep = _rows(len(record.rows))
    col = {name: i for i, name in enumerate(record.columns)}
    rows = [record.rows[k] for k in keep]
    pose = np.array([[r[col[c]] for c in EGO_POSE_COLUMNS[:3]] for r in rows], dtype=float)
    n_obj = len(scenario.scene_objects())
    objects = [[[r[col[f"obj{i}_{c}"]] for c in OBJECT_POSE_COLUMNS] for r in rows] for i in range(n_obj)]
    road = build_road(scenario.road)
    departure = departure_m(road, ego_corners(scenario, pose)) if road is not None else 0.0
    contact = record.contact
    trace = {"t_s": [r[col["time_s"]] for r in rows], "ego": pose.tolist(),
             "speed_mps": [r[col["speed_mps"]] for r in rows], "objects": objects, "contact": contact}
    hit = None if contact is None else contact.get("object_name")
    return PlanarOutcome(hit, round(departure, 4) if math.isfinite(departure) else departure, trace)
