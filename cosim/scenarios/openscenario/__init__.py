"""OpenSCENARIO 1.x and OpenDRIVE: import (:func:`read_xosc`) and export (:mod:`.export`).

The subset, how it maps onto crd's scenario keys, and the errors: docs/openscenario.md.
Needs the ``xosc`` extra (lxml; scenariogeneration for export).
"""

from __future__ import annotations


def read_xosc(path, ego=None):
    """See :func:`cosim.scenarios.openscenario.reader.read_xosc` (imported on use: lxml is an extra)."""
    from .reader import read_xosc as read

    return read(path, ego)
