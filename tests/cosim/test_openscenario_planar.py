"""OpenSCENARIO/OpenDRIVE files that need the plane: a curved road (line, arc, spiral) imports as ``[road]``.

The files are written with scenariogeneration (not crd's exporter). The imported reference line,
turned and moved back into the file's frame, must end where the OpenDRIVE file's next geometry
record starts (scenariogeneration computes those records itself), and ``crd run`` of the file must
keep the ego in its lane through the curve.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("scenariogeneration")
from lxml import etree  # noqa: E402
from scenariogeneration import xodr, xosc  # noqa: E402

from cosim.cli.main import main as crd  # noqa: E402
from cosim.results.run_view import load_run_view  # noqa: E402
from cosim.scenarios.openscenario import read_xosc  # noqa: E402
from cosim.scenarios.openscenario.reader import xosc_to_dict  # noqa: E402
from cosim.world.reference_line import Arc, Line, PlanView, Spiral  # noqa: E402

CURVE_1PM = 1 / 150.0
EGO_S_M = 10.0
EGO = (4.5, 1.8, 1.4)  # length, width, box centre ahead of the reference point (m)


def _write(out: Path, geometries: list, name: str = "curve") -> Path:
    """A road of ``geometries`` (one 3.5 m lane each way) and the ego at 50 km/h in lane -1, s = 10 m."""
    road = xodr.create_road(geometries, id=1, left_lanes=1, right_lanes=1, lane_width=3.5)
    odr = xodr.OpenDrive(name)
    odr.add_road(road)
    odr.adjust_roads_and_lanes()
    odr.write_xml(str(out / f"{name}.xodr"))
    length, width, centre = EGO
    box = xosc.BoundingBox(width, length, 1.4, centre, 0.0, 0.7)
    ego = xosc.Vehicle("car", xosc.VehicleCategory.car, box, xosc.Axle(0.5, 0.65, 1.6, 2.7, 0.33),
                       xosc.Axle(0.0, 0.65, 1.6, 0.0, 0.33), 60.0, 8.0, 10.0)
    entities = xosc.Entities()
    entities.add_scenario_object("Ego", ego)
    init = xosc.Init()
    init.add_init_action("Ego", xosc.TeleportAction(xosc.LanePosition(EGO_S_M, 0.0, -1, 1)))
    init.add_init_action("Ego", xosc.AbsoluteSpeedAction(50 / 3.6, xosc.TransitionDynamics(
        xosc.DynamicsShapes.step, xosc.DynamicsDimension.time, 0.0)))
    stop = xosc.ValueTrigger("end", 0.0, xosc.ConditionEdge.rising,
                             xosc.SimulationTimeCondition(22.0, xosc.Rule.greaterThan), "stop")
    scenario = xosc.Scenario(name, "crd tests", xosc.ParameterDeclarations(), entities, xosc.StoryBoard(init, stop),
                             xosc.RoadNetwork(roadfile=f"{name}.xodr"), xosc.Catalog(), osc_minor_version=1)
    path = out / f"{name}.xosc"
    scenario.write_xml(str(path))
    return path


def _records(xodr_path: Path) -> list[tuple[float, float, float, float]]:
    """The file's ``<geometry>`` records: (s, x, y, hdg)."""
    return [tuple(float(g.get(k)) for k in ("s", "x", "y", "hdg"))
            for g in etree.parse(str(xodr_path)).iter("geometry")]


def _to_file_frame(xosc_path: Path, x: float, y: float, h: float) -> tuple[float, float, float]:
    """crd's frame back to the file's: the ego's reference point at (sx, sy) heading sh (lane -1, s = 10)."""
    _, sx, sy, sh = _records(xosc_path.with_suffix(".xodr"))[0]
    sx, sy = sx + EGO_S_M * math.cos(sh) + 1.75 * math.sin(sh), sy + EGO_S_M * math.sin(sh) - 1.75 * math.cos(sh)
    x = x + EGO[0] / 2 + EGO[2]  # crd's origin is the front bumper, the file's the reference point
    return sx + x * math.cos(sh) - y * math.sin(sh), sy + x * math.sin(sh) + y * math.cos(sh), sh + h


SEGMENTS = {"line": lambda g: Line(g["length_m"]), "arc": lambda g: Arc(g["length_m"], g["curvature_1pm"]),
            "spiral": lambda g: Spiral(g["length_m"], g["curvature_start_1pm"], g["curvature_end_1pm"])}


@pytest.mark.parametrize("kind", ["arc", "spiral"])
def test_a_curved_road_imports_as_the_planar_road(tmp_path: Path, kind: str) -> None:
    if kind == "arc":
        geoms = [xodr.Line(50.0), xodr.Arc(CURVE_1PM, angle=math.pi / 2), xodr.Line(80.0)]
    else:
        geoms = [xodr.Line(50.0), xodr.Spiral(0.0, CURVE_1PM, 40.0), xodr.Arc(CURVE_1PM, 60.0),
                 xodr.Spiral(CURVE_1PM, 0.0, 40.0), xodr.Line(80.0)]
    path = _write(tmp_path, geoms)
    road = xosc_to_dict(path)["road"]
    kinds = ["line", "arc", "line"] if kind == "arc" else ["line", "spiral", "arc", "spiral", "line"]
    assert [g["kind"] for g in road["geometry"]] == kinds
    plan = PlanView.chained([SEGMENTS[g["kind"]](g) for g in road["geometry"]], road["x_m"], road["y_m"],
                            road["heading_rad"])
    for placed, (s, x, y, h) in zip(plan.placed, _records(path.with_suffix(".xodr"))):
        mine = _to_file_frame(path, placed.x_m, placed.y_m, placed.heading_rad)
        assert placed.s_m == pytest.approx(s, abs=1e-9)
        tol = 1e-9 if kind == "arc" else 1e-6  # scenariogeneration's clothoids are its own numerics
        assert mine == pytest.approx((x, y, h), abs=tol)
    scenario = read_xosc(path)
    assert scenario.driver.steering.model == "path_following" and scenario.driver.steering.lane == -1


def test_crd_runs_the_curved_road_in_its_lane(tmp_path: Path) -> None:
    path = _write(tmp_path, [xodr.Line(50.0), xodr.Arc(CURVE_1PM, angle=math.pi / 2), xodr.Line(80.0)])
    out = tmp_path / "run"
    assert crd(["run", str(path), "--out", str(out)]) == 0
    strategy = json.loads((out / "metrics.json").read_text())["runs"][0]["strategy"]
    view = load_run_view(out)
    ego = view.tracks[strategy].ego
    offsets = np.array([view.road.to_st(x, y)[1] for x, y, _ in ego]) + 1.75  # from lane -1's centre
    assert np.abs(offsets).max() < 0.5
    assert ego[:, 2].max() == pytest.approx(math.pi / 2, abs=0.02)  # it turned through the quarter circle
