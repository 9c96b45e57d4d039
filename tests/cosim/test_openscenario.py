"""OpenSCENARIO/OpenDRIVE export and import (issue 24): independent parser, ASAM XSDs, exact round trips.

The XSDs are the ones scenariogeneration ships (OpenSCENARIO 1.0-1.3, OpenDRIVE 1.7).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

sg = pytest.importorskip("scenariogeneration")
xmlschema = pytest.importorskip("xmlschema")

from cosim.cli.main import main  # noqa: E402
from cosim.cli.scenarios import bundled_scenarios, find_scenario  # noqa: E402
from cosim.matrix.catalogue import bundled, load_catalogue  # noqa: E402
from cosim.scenarios.loader import load_scenario, scenario_from_dict  # noqa: E402
from cosim.scenarios.openscenario import read_xosc  # noqa: E402
from cosim.scenarios.openscenario.export import ExportError, export_xosc  # noqa: E402

SCHEMAS = Path(sg.__file__).resolve().parents[1] / "schemas"
PAPER = Path(__file__).resolve().parents[2] / "cosim" / "scenarios" / "paper_cyclist.toml"
#: the benchmark's planar scene: eight objects placed and moved every way crd has
PLANAR_8 = Path(__file__).resolve().parents[2] / "benchmarks" / "planar_8_objects.toml"
#: every bundled scenario (1-D and planar) and the benchmark scene
SCENES = [p.stem for p in bundled_scenarios()] + [str(PLANAR_8)]
PLANAR = ["lane_change_parked_car", "curve_parked_car", "crossing_pedestrian", "paper_cyclist_road"]


def _cells():
    return [(name, cell) for name in sorted(bundled()) for cell in load_catalogue(name).cells]


def _same_scene(a, b) -> bool:
    """Equal scenarios; one object may come back as [object] or [[objects]] (the same scene)."""
    norm = lambda s: dataclasses.replace(s, object=None, objects=s.scene_objects())  # noqa: E731
    return norm(a) == norm(b)


@pytest.fixture(scope="module")
def schemas():
    return xmlschema.XMLSchema(str(SCHEMAS / "OpenSCENARIO_1_2.xsd")), xmlschema.XMLSchema(
        str(SCHEMAS / "opendrive_17_core.xsd"))


def _scene(name: str):
    return load_scenario(find_scenario(name))


@pytest.mark.parametrize("cell_id", ["paper", "CCRb-50", "cut-out-50", "lead-brakes-far-ahead-50",
                                     "adjacent-stationary-car-80", "CCCscp-near-gvt20-20", "CPNCO-25-10",
                                     "kerb-stop-20", "lead-turns-off-50", *PLANAR, "planar_8_objects"])
def test_export_validates_and_parses_with_scenariogeneration(tmp_path: Path, schemas, cell_id: str) -> None:
    if cell_id == "paper":
        scenario = load_scenario(PAPER)
    elif cell_id in PLANAR or cell_id == "planar_8_objects":
        scenario = _scene(str(PLANAR_8) if cell_id == "planar_8_objects" else cell_id)
    else:
        scenario = scenario_from_dict(next(c for _, c in _cells() if c.cell_id == cell_id).scenario_dict())
    xosc_path, xodr_path = export_xosc(scenario, tmp_path, "s")
    osc_xsd, odr_xsd = schemas
    osc_xsd.validate(str(xosc_path))
    odr_xsd.validate(str(xodr_path))
    parsed = sg.xosc.ParseOpenScenario(str(xosc_path))
    names = [o.name for o in parsed.entities.scenario_objects]
    assert names == ["Ego"] + [o.name for o in scenario.scene_objects()]
    assert parsed.header.description == scenario.scenario.name


#: cells that the export refuses today, per catalogue, and why (each reason a phrase of the one-line error).
#: None since a box placed by ``pose`` on the ego's axis is a RelativeObjectPosition and a trajectory's changing
#: speed SpeedAction segments (102 cells of ncap_junction, ncap_vru and planar_false_positive before). Pinned,
#: so that a cell the export starts to refuse fails here.
REFUSED_CELLS: dict[str, int] = {}
REFUSED_BECAUSE: tuple[str, ...] = ()


def test_every_bundled_cell_round_trips_exactly_or_is_refused_in_one_line(tmp_path: Path) -> None:
    cells = _cells()
    assert len(cells) > 50
    refused: dict[str, int] = {}
    for name, cell in cells:
        try:
            export_xosc(scenario_from_dict(cell.scenario_dict(0, 3)), tmp_path, cell.cell_id)
        except ExportError as exc:
            assert "\n" not in str(exc) and any(r in str(exc) for r in REFUSED_BECAUSE), (name, cell.cell_id, exc)
            refused[name] = refused.get(name, 0) + 1
            continue
        for phase in (0, 2):
            scenario = scenario_from_dict(cell.scenario_dict(phase, 3))
            back = read_xosc(export_xosc(scenario, tmp_path, cell.cell_id)[0])
            assert _same_scene(scenario, back), (name, cell.cell_id, phase)
    assert refused == REFUSED_CELLS
    paper = load_scenario(PAPER)
    assert read_xosc(export_xosc(paper, tmp_path, "paper")[0]) == paper


@pytest.mark.parametrize("name", SCENES, ids=[Path(n).stem for n in SCENES])
def test_every_bundled_scenario_round_trips_exactly(tmp_path: Path, name: str) -> None:
    """The planar ones too: [road], steering, target classes, road poses, lane and waypoint trajectories, crossings."""
    scenario = _scene(name)
    back = read_xosc(export_xosc(scenario, tmp_path, Path(name).stem)[0])
    assert back == scenario  # [object] stays [object], [[objects]] stays [[objects]]
    assert back.planar == scenario.planar


def _outputs(run: Path) -> dict[str, bytes]:
    """Every file of a run, the wall time masked out and the BLF log as its decoded frames."""
    import can

    out = {}
    for path in sorted(p for p in run.rglob("*") if p.is_file()):
        rel = str(path.relative_to(run))
        if path.suffix == ".blf":
            with can.BLFReader(str(path)) as reader:
                out[rel] = repr([(m.timestamp, m.arbitration_id, bytes(m.data)) for m in reader]).encode()
        elif path.name == "metrics.json":
            data = json.loads(path.read_text())
            for record in data["runs"]:
                record.pop("wall_time_s")
            out[rel] = json.dumps(data, sort_keys=True).encode()
        elif path.name == "report.md":  # its table's last column is the wall time
            lines = path.read_text().splitlines()
            assert lines[4].endswith("| wall (s) |")
            out[rel] = "\n".join(line.rsplit("|", 2)[0] if line.startswith("|") else line for line in lines).encode()
        else:
            out[rel] = path.read_bytes()
    return out


@pytest.mark.slow
@pytest.mark.parametrize("name", SCENES, ids=[Path(n).stem for n in SCENES])
def test_export_then_import_gives_the_same_run(tmp_path: Path, name: str) -> None:
    key = tmp_path / "key.hex"  # one SecOC key for both runs (else each run draws a fresh one: other MACs)
    key.write_text("00112233445566778899aabbccddeeff\n")
    key.chmod(0o600)
    stem = Path(name).stem
    assert main(["scenarios", "export", name, "--format", "xosc", "--out", str(tmp_path / "x")]) == 0
    # one run directory name for both: the bird's-eye plot's title names it
    code = main(["run", name, "--key-file", str(key), "--out", str(tmp_path / "a" / "run")])
    assert code in (0, 3)  # 3: a failed check, as braking_lead's states it does today
    assert main(["run", str(tmp_path / "x" / f"{stem}.xosc"), "--key-file", str(key),
                 "--out", str(tmp_path / "b" / "run")]) == code
    a, b = _outputs(tmp_path / "a" / "run"), _outputs(tmp_path / "b" / "run")
    assert "tightening/timeseries.csv" in a and "tightening/can.blf" in a
    assert ("scene.json" in a) == (stem in PLANAR or stem == "planar_8_objects")
    assert a.keys() == b.keys()
    for file in a:
        assert a[file] == b[file], file


def _planar(objects: list[dict]) -> dict:
    """A curved-road scene (line, spiral, arc) with a path-following ego and ``objects``."""
    return {"scenario": {"name": "odd", "duration_s": 5.0}, "plant": {"initial_speed_mps": 10.0},
            "driver": {"model": "hold_speed", "set_speed_mps": 10.0, "steering": {"lane": -1}},
            "road": {"y_m": 1.75, "geometry": [{"kind": "line", "length_m": 30.0},
                                               {"kind": "spiral", "length_m": 40.0, "curvature_start_1pm": 0.0,
                                                "curvature_end_1pm": -0.01},
                                               {"kind": "arc", "length_m": 60.0, "curvature_1pm": -0.01}],
                     "lane_sections": [{"left_m": [3.5], "right_m": [3.5, 3.0]}]},
            "objects": objects}


ODD = [  # placements and motions the bundled scenes do not use
    {"name": "askew", "target_class": "GVT", "pose": {"x_m": 40.0, "y_m": 6.0, "heading_rad": -2.5}},
    {"name": "on the spiral", "target_class": "EPTa", "road_pose": {"s_m": 45.0, "t_m": -5.0, "heading_rad": 1.2},
     "speed_mps": 0.5},
    {"name": "late walker", "target_class": "EPTc", "trajectory": {
        "waypoints": [[50.0, -8.0], [52.5, -1.0], [60.0, 3.0]], "speeds": [[0.0, 1.5]], "start": "time",
        "start_value": 1.25}},
    {"name": "lane rider", "target_class": "EMT", "trajectory": {
        "lane": -2, "lane_offset_m": 0.25, "start_s_m": 12.5, "speeds": [[0.0, 8.0]], "start": "time",
        "start_value": 0.5}},
    {"name": "diagonal", "target_class": "EBTa", "crossing": {
        "x_m": 45.3, "y_m": -0.7, "heading_rad": 2.1, "start_distance_m": 6.7, "accel_distance_m": 1.3,
        "speed_mps": 4.1}},
]


def test_other_placements_round_trip_exactly(tmp_path: Path) -> None:
    """A world pose across the ego, a road pose on a spiral, a later waypoint and lane trajectory on a spiral and an
    arc, a skewed crossing."""
    scenario = scenario_from_dict(_planar(ODD))
    back = read_xosc(export_xosc(scenario, tmp_path, "odd")[0])
    assert back == scenario


def _walk(speeds: list, **start) -> dict:
    return {"name": "x", "trajectory": {"waypoints": [[5.0, -4.0], [5.0, 4.0]], "speeds": speeds, **start}}


UNEXPORTABLE = {  # an object the export cannot carry exactly -> what the error names
    "speeds over time": (_walk([[0.0, 1.0], [2.0, 3.0]], speeds_over="time"), "trajectory speeds .* over time"),
    "a last knot of the same speed": (_walk([[0.0, 1.0], [2.0, 3.0], [4.0, 3.0]]), "read back as"),
    "knots after a later start in motion": (_walk([[0.0, 1.0], [2.0, 1.0], [4.0, 3.0]], start="time",
                                                  start_value=1.0), "TraveledDistanceCondition"),
    "ego distance start": (_walk([[0.0, 1.0]], start="ego_distance", start_value=20.0, start_point=[5.0, 0.0]),
                           "trajectory start 'ego_distance'"),
    "braking road pose": ({"name": "x", "road_pose": {"s_m": 5.0}, "speed_mps": 3.0, "brake_decel_mps2": 2.0,
                           "brake_at_s": 1.0}, "braking"),
}


@pytest.mark.parametrize("case", sorted(UNEXPORTABLE))
def test_what_the_export_cannot_carry_is_an_error(tmp_path: Path, case: str) -> None:
    from cosim.scenarios.openscenario.export import ExportError

    obj, words = UNEXPORTABLE[case]
    with pytest.raises(ExportError, match=f"object 'x'.*{words}"):
        export_xosc(scenario_from_dict(_planar([obj])), tmp_path, "bad")
