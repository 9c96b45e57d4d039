"""Catalogue cells whose scenario is an OpenSCENARIO file (a series' ``xosc`` key).

The file gives the whole encounter (:func:`cosim.scenarios.openscenario.read_xosc`);
the series gives what the scoring reads (``group``, ``ego_speed_kmh``,
``target``, ``target_speed_kmh``, the requirement keys). The keys the file
gives are merged over the catalogue's ``[scenario]`` table (the file wins).
A cell's radar phase ``i`` of ``N`` shifts the encounter as for a built cell
(:mod:`cosim.matrix.catalogue`): each object starts ``closing * 0.05 * i/N`` m
further and its time triggers move by ``0.05 * i/N`` s. The ego's start speed
must be the series' ``ego_speed_kmh`` (checked), so the score's row is the run's.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

from ..scenarios.config import OBJECT_TRACK_PERIOD_S

KMH = 3.6
SPEED_TOL_MPS = 1e-9
TIME_KEYS = ("brake_at_s", "lateral_at_s")


def resolve(params: dict[str, Any], base_dir: Path) -> None:
    """Make a cell's ``xosc`` path absolute (relative paths are relative to the catalogue file)."""
    if params.get("xosc") is not None:
        params["xosc"] = str((base_dir / params["xosc"]).resolve())


def _shifted(obj: dict[str, Any], ego_speed_mps: float, shift_s: float) -> dict[str, Any]:
    obj = dict(obj)
    if shift_s:
        obj["position_m"] += max(0.0, ego_speed_mps - obj["speed_mps"]) * shift_s
    for key in TIME_KEYS:
        if shift_s and obj.get(key) is not None:
            obj[key] += shift_s
    return obj


def scenario_dict(params: Mapping[str, Any], base: Mapping[str, Any], merge, phase: int, phases: int) -> dict:
    """The cell's scenario mapping from its file, merged over the catalogue's ``[scenario]`` table."""
    from ..scenarios.openscenario.reader import xosc_to_dict  # lxml: the xosc extra

    data = xosc_to_dict(params["xosc"], params.get("ego"))
    v = data["plant"]["initial_speed_mps"]
    if abs(v - params["ego_speed_kmh"] / KMH) > SPEED_TOL_MPS:
        raise ValueError(f"{params['xosc']}: the ego starts at {v * KMH:g} km/h, the series says "
                         f"ego_speed_kmh = {params['ego_speed_kmh']:g}")
    shift_s = OBJECT_TRACK_PERIOD_S * phase / phases
    objs = data.pop("objects", None) or [data.pop("object")]
    data.pop("object", None)
    live = [_shifted(o, v, shift_s) for o in objs if o.get("enabled", True)]
    if live:
        data["objects"] = live
    else:
        data["object"] = {"enabled": False}
    return merge(base, data)
