"""The ECU's chosen stopping path for the bird's-eye view, from a planar run's region columns.

A planar run's ``timeseries.csv`` carries the last ``EcuRegionStatus`` the ECU sent
(``REGION_COLUMNS``, :mod:`cosim.results.run_record`): the contingency, the chosen path's curvature
and its stopping distance. At each row where that report changes, and at every row while a path is
reported (the band moves with the car while the report is held), the view draws the stopping
path as the ECU chose it: a band of the ego's width from its front bumper along an arc of that
curvature, as long as the stopping distance (the arc from the front bumper, not from the rear
axle the ECU's paths start at: a drawing aid), labelled with the contingency's DBC name. A report
of ``NOT_EVALUATED`` or a missing value draws nothing. ``stopping_region.json``, when a run has
one, takes precedence (:mod:`cosim.results.run_view`).
"""

from __future__ import annotations

import math

import numpy as np

from can_dbc.contract import enumeration

from .scene_file import Body

#: ``EcuRegionStatus.Contingency`` value -> its DBC name
CONTINGENCY_NAMES = {int(value): name for value, name in enumeration("EcuRegionStatus", "Contingency").items()}
_COLUMNS = ("region_contingency", "region_curvature_1pm", "region_stopping_m")
ARC_SAMPLES = 16


def stopping_band(pose: tuple[float, float, float], body: Body, curvature_1pm: float, length_m: float) -> np.ndarray:
    """The outline ``(2 ARC_SAMPLES + 2, 2)`` of a band of the body's width along an arc from its front bumper."""
    x, y, yaw = pose
    fx, fy = x + body.front_m * math.cos(yaw), y + body.front_m * math.sin(yaw)
    s = np.linspace(0.0, max(0.0, length_m), ARC_SAMPLES + 1)
    heading = yaw + curvature_1pm * s
    if abs(curvature_1pm) < 1e-9:
        px, py = fx + s * math.cos(yaw), fy + s * math.sin(yaw)
    else:
        px = fx + (np.sin(heading) - math.sin(yaw)) / curvature_1pm
        py = fy - (np.cos(heading) - math.cos(yaw)) / curvature_1pm
    nx, ny, half = -np.sin(heading), np.cos(heading), body.width_m / 2.0
    left = np.column_stack([px + half * nx, py + half * ny])
    right = np.column_stack([px - half * nx, py - half * ny])
    return np.vstack([left, right[::-1]])


def regions_from_columns(columns: dict[str, list[str]], t_s: np.ndarray, pose: np.ndarray,
                         body: Body) -> tuple[np.ndarray, tuple[np.ndarray, ...], tuple[str, ...]] | None:
    """(times, polygons, labels) at every row whose region report changed or that reports a path (the module
    docstring); None when the run has no region columns."""
    if not all(name in columns for name in _COLUMNS):
        return None
    kind, curvature, stopping = (np.array(columns[name], dtype=float) for name in _COLUMNS)
    report = np.column_stack([kind, curvature, stopping])
    changed = np.ones(len(t_s), dtype=bool)
    changed[1:] = np.any((report[1:] != report[:-1]) & ~(np.isnan(report[1:]) & np.isnan(report[:-1])), axis=1)
    reported = np.isfinite(kind) & np.isfinite(curvature) & np.isfinite(stopping)
    times, polygons, labels = [], [], []
    for j in np.flatnonzero(changed | reported):
        name = CONTINGENCY_NAMES.get(int(kind[j]), "") if math.isfinite(kind[j]) else ""
        drawn = name not in ("", "NOT_EVALUATED") and math.isfinite(curvature[j]) and math.isfinite(stopping[j])
        times.append(float(t_s[j]))
        polygons.append(stopping_band(tuple(pose[j]), body, curvature[j], stopping[j]) if drawn else np.empty((0, 2)))
        labels.append(name if drawn else "")
    return np.array(times), tuple(polygons), tuple(labels)
