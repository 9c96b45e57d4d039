"""Polygons of a :class:`ecu.core.region.decision.RegionDecision` for the bird's-eye view.

All in the ego's frame from the front bumper (the tracks' frame), x forward, y left, as float
arrays with a last axis of 2: the footprint boxes of a stopping path, the outline of their union
(``[rear right, rear left, front left of every box, front right of every box backwards]``; a
drawing aid, not the exact union), and the objects' boxes or stopping regions.
"""

from __future__ import annotations

import numpy as np

from .decision import RegionDecision
from .objects import corners
from .overlap import corner_points
from .params import RegionParams


def _to_bumper(points: np.ndarray, params: RegionParams) -> np.ndarray:
    """Complex rear-axle points -> float ``(.., 2)`` in the bumper frame."""
    return np.stack((points.real - params.rear_axle_to_front_m, points.imag), axis=-1)


def footprint_boxes(decision: RegionDecision, row: int, params: RegionParams) -> np.ndarray:
    """The corners (front left, rear left, rear right, front right) of every box of ``row``, shape ``(M, 4, 2)``."""
    return _to_bumper(corner_points(decision.paths, decision.box)[row], params)


def stopping_path_outline(decision: RegionDecision, row: int, params: RegionParams) -> np.ndarray:
    """The outline of ``row``'s footprint boxes, shape ``(2 M + 2, 2)`` (module docstring)."""
    boxes = corner_points(decision.paths, decision.box)[row]
    ring = np.concatenate(([boxes[0, 2], boxes[0, 1]], boxes[:, 0], boxes[::-1, 3]))
    return _to_bumper(ring, params)


def object_polygons(decision: RegionDecision, params: RegionParams) -> np.ndarray:
    """Every object's box (standing) or stopping region (moving), inflated, shape ``(K, 4, 2)``."""
    return _to_bumper(corners(decision.objects), params)
