"""The stopping region in the plane (issue 22, item 1): pure geometry and the contingency choice.

No I/O, no clock; numpy for the vectorised overlap. Wired into :func:`ecu.core.step` by :mod:`ecu.core.planar`.
Modules, in the order of the flow: ``params`` (geometry, limits, object capabilities, with
sources), ``paths`` (the followable paths and their stopping paths), ``objects`` (what the other
tracks occupy), ``overlap`` (footprints and separations), ``road`` (lanes and the road's bounds),
``decision`` (Stopping Path Disjointness and the contingency rules), ``tightening`` (the joint
bounds biased by proximity) and ``drawing`` (polygons for the bird's-eye view).
See docs/stopping-region.md.
"""

from .decision import Contingency, RegionDecision, decide
from .objects import TrackBox
from .params import CAPABILITIES, ClassCapability, RegionParams, region_params
from .paths import EgoState
from .road import Road
from .tightening import JointBounds, tightened_bounds

__all__ = [
    "CAPABILITIES", "ClassCapability", "Contingency", "EgoState", "JointBounds", "RegionDecision",
    "RegionParams", "Road", "TrackBox", "decide", "region_params", "tightened_bounds",
]
