"""The planar catalogues (ncap_vru, ncap_junction, planar_false_positive, emergency_steering): the protocol rules
their data and scorings encode, one test per rule that could be wrong, and a few representative runs."""

import math

import numpy as np
import pytest

from cosim.errors import ConfigError
from cosim.matrix.catalogue import load_catalogue
from cosim.matrix.planar_junction import turn_path
from cosim.matrix.planar_scenes import SceneCell
from cosim.matrix.scoring import Outcome
from cosim.matrix.scorings import score_cell
from cosim.matrix.scorings.ncap_fc import extended_fraction, fc_colour, scenario_of, scenario_points
from cosim.matrix.planar_outcome import PlanarOutcome
from cosim.scenarios.loader import scenario_from_dict
from cosim.world.scene_build import build_objects, build_road
from cosim.world.trajectory import EgoState

EGO_WIDTH_M = 1.815  # the catalogues' ego: the default [plant] (Euro NCAP reference VUT)


def cells(name):
    return {c.cell_id: c for c in load_catalogue(name).cells}


def outcome(collided=False, impact=0.0, n=0, departure=None, hit=None):
    planar = None if departure is None else PlanarOutcome(hit, departure, {})
    return Outcome(collided, impact, n, None, 1.0, None, 5.0, 1.0, None, planar)


def objects_at(cell, t_s, ego_speed_mps=None):
    """The cell's objects at ``t_s`` with the ego at constant speed from x = 0 (its front), triggers observed
    every 10 ms from the start: (object, box centre, state) each."""
    sc = scenario_from_dict(cell.scenario_dict())
    objs = build_objects(sc, build_road(sc.road))
    v = sc.plant.initial_speed_mps if ego_speed_mps is None else ego_speed_mps
    for k in range(int(round(t_s * 100)) + 1):
        t = k / 100.0
        for o in objs:
            o.motion.observe(t, 1e9, EgoState(v * t, 0.0, 0.0, v))
    return [(o, o.centre(o.motion.state(t_s)), o.motion.state(t_s)) for o in objs]


# -- ncap_fc: colour bands by test speed, avoidance scenarios, points -----------------------------------------
@pytest.mark.parametrize("speed, impact, colour", [
    (10, 0.5, "red"), (20, 19.9, "red"),                        # 10, 20 km/h: avoid or red
    (30, 10.0, "brown"), (30, 10.01, "red"),                     # 30: brown up to 10
    (40, 10.0, "orange"), (40, 10.01, "brown"), (40, 20.0, "brown"), (40, 20.01, "red"),
    (50, 10.0, "yellow"), (50, 20.0, "orange"), (50, 30.0, "brown"), (60, 30.01, "red"), (60, 0.01, "yellow"),
])
def test_fc_colour_band_edges_depend_on_the_test_speed(speed, impact, colour):
    assert fc_colour(speed, impact, True) == colour
    assert fc_colour(speed, impact, False) == "green"


def test_junction_scenarios_are_red_on_any_contact_and_groups_map_to_their_scenario():
    row = score_cell("ncap_fc", {"group": "CCCscp-near-gvt50", "ego_speed_kmh": 60}, outcome(True, 2.0))
    assert row["colour"] == "red" and not row["passed"]
    row = score_cell("ncap_fc", {"group": "CPNA-25", "ego_speed_kmh": 60}, outcome(True, 2.0))
    assert row["colour"] == "yellow" and row["score"] == 0.75
    assert scenario_of("CBNAO-25") == "CBNAO" and scenario_of("CBNA-25") == "CBNA"


@pytest.mark.parametrize("share, fraction", [(0.49, 0.0), (0.5, 0.5), (0.74, 0.5), (0.75, 0.75), (0.99, 0.75),
                                             (1.0, 1.0)])
def test_extended_range_share_is_stepped(share, fraction):
    assert extended_fraction(share) == fraction


def test_scenario_points_normalise_standard_cells_and_step_extended_ones():
    table = load_catalogue("ncap_vru").scoring_table
    rows = [{"group": "CPNA-25", "colour": c} for c in ("green", "yellow", "red")] + \
           [{"group": "CPNA-10", "colour": c, "extended": True} for c in ("green", "brown", "red", "orange")]
    pts = scenario_points(rows, table)
    assert pts["CPNA"] == pytest.approx(round(0.5 * (1.0 + 0.75 + 0.0) / 3, 2) + 0.0625 * 0.75)
    assert pts["total"] == pts["CPNA"]


def test_protocol_points_are_the_published_day_tables():
    vru = load_catalogue("ncap_vru").scoring_table
    assert dict(vru.points) == {"CPNA": 0.5, "CPFA": 0.5, "CPNCO": 1.0, "CBNA": 1.0, "CBFA": 1.0, "CBNAO": 2.0,
                                "CPLA": 3.0, "CBLA": 2.0}
    assert sum(vru.extended_points.values()) == pytest.approx(0.0625 * 2 + 0.125 * 3 + 0.25)
    junction = load_catalogue("ncap_junction").scoring_table
    assert dict(junction.points) == {"CCFtap": 4.0, "CCCscp": 6.0}
    assert dict(junction.extended_points) == {"CCFtap": 0.5, "CCCscp": 0.75}


# -- the grids ---------------------------------------------------------------------------------------------
def test_vru_standard_and_extended_impact_positions():
    cat = load_catalogue("ncap_vru")
    std = {}
    for c in cat.cells:
        std.setdefault(scenario_of(c.group), set()).add((c.params["layout"]["impact_pct"], c.params["extended"]))
    assert {p for p, e in std["CPNA"] if not e} == {25, 50, 75} and {p for p, e in std["CPNA"] if e} == {10, 90}
    assert {p for p, e in std["CPFA"] if not e} == {50}
    assert {p for p, e in std["CPNCO"] if not e} == {50} and {p for p, e in std["CPNCO"]} == {25, 50, 75}
    assert {p for p, e in std["CBNA"] if not e} == {25, 50} and {p for p, e in std["CBFA"] if not e} == {50, 75}
    assert {c.ego_speed_kmh for c in cat.cells if c.group == "CPNA-50"} == {10, 20, 30, 40, 50, 60}


def test_cccscp_leaves_out_the_untested_cells_and_marks_the_extended_ones():
    grid = {(c.ego_speed_kmh, c.params["target_speed_kmh"], c.params["layout"]["side"]): bool(c.params.get("extended"))
            for c in load_catalogue("ncap_junction").cells if c.group.startswith("CCCscp")}
    assert len(grid) == 66
    assert not any((40 <= v <= 60 and g >= 70) or (v >= 70 and g >= 40) for v, g, _ in grid)
    ext = {(v, g) for (v, g, _), e in grid.items() if e}
    assert ext == {(v, g) for v in (20, 30) for g in (70, 80)} | {(v, g) for v in (70, 80) for g in (20, 30)}


# -- where targets meet the ego ---------------------------------------------------------------------------------
@pytest.mark.parametrize("cell_id, side", [("CPNA-25-40", 1), ("CPNA-75-20", 1), ("CPFA-10-60", -1),
                                           ("CBNA-50-30", 1), ("CBFA-75-50", -1)])
def test_crossing_target_reference_point_meets_the_impact_location(cell_id, side):
    cell = cells("ncap_vru")[cell_id]
    lay = cell.params["layout"]
    x_sync = cell.scenario_dict()["objects"][0]["crossing"]["x_m"]
    v = cell.ego_speed_kmh / 3.6
    (obj, (cx, cy), st), *_ = objects_at(cell, x_sync / v)
    reference_y = cy + side * lay["reference_m"]  # the reference point lies ahead of the centre along the heading
    assert reference_y == pytest.approx((lay["impact_pct"] / 100 - 0.5) * EGO_WIDTH_M, abs=0.03)
    assert st.speed_mps == pytest.approx(cell.params["target_speed_kmh"] / 3.6)  # steady by then
    start = objects_at(cell, 0.0)[0][1][1] + side * lay["reference_m"]
    assert start == pytest.approx(-side * lay["start_distance_m"])  # starts the protocol's distance from the 50 % point


@pytest.mark.parametrize("cell_id, x_vut, x_gvt", [("CCFtap-gvt30-10", 9.57, 29.17), ("CCFtap-gvt60-20", 19.47, 58.33)])
def test_ccftap_synchronisation_is_the_protocols(cell_id, x_vut, x_gvt):
    cell = cells("ncap_junction")[cell_id]
    path = turn_path(SceneCell(cell_id, cell.params, cell.params["layout"], cell.target, EGO_WIDTH_M, 4.358, 0.0))
    i = int((path[:, 1] >= 3.5).argmax())
    x_cp = float(np.interp(3.5, path[i - 1:i + 1, 1], path[i - 1:i + 1, 0]))  # where the ego's path crosses lane 1
    v = cell.ego_speed_kmh / 3.6
    (obj, (cx, cy), st), = objects_at(cell, (x_cp - x_vut) / v)
    assert cy == pytest.approx(3.5) and cx - obj.half_length_m - x_cp == pytest.approx(x_gvt, abs=0.05)
    headings = [math.atan2(b[1] - a[1], b[0] - a[0]) for a, b in zip(path[:-1], path[1:])]
    lay = cell.params["layout"]
    turned = 2 * lay["clothoid_deg"] + lay["arc_deg"]  # the published angles give 89.99 to 90.00 degrees
    assert math.degrees(headings[-1]) == pytest.approx(turned, abs=1e-6) and turned == pytest.approx(90.0, abs=0.011)


def test_cccscp_gvt_front_meets_the_middle_of_the_ego_front():
    for cell_id, sign in (("CCCscp-near-gvt50-40", 1), ("CCCscp-far-gvt20-60", -1)):
        cell = cells("ncap_junction")[cell_id]
        gvt = cell.scenario_dict()["objects"][0]["trajectory"]["waypoints"]
        v = cell.ego_speed_kmh / 3.6
        (obj, (cx, cy), _), *parked = objects_at(cell, gvt[0][0] / v)
        assert cx == pytest.approx(gvt[0][0]) and cy + sign * obj.half_length_m == pytest.approx(0.0, abs=1e-6)
        assert len(parked) == 3  # the standard range's obstruction


# -- the emergency-steering cells and their scoring ---------------------------------------------------------------
def test_emergency_steering_cells_need_steering_where_the_data_says():
    """The catalogue's claim: braking alone (8.9 m/s^2, 0.35 s) cannot stop within the uncovered distance at
    70 km/h and above, and can at 50 km/h in the cut-out."""
    for c in load_catalogue("emergency_steering").cells:
        data = c.scenario_dict()
        v = c.ego_speed_kmh / 3.6
        reveal_m = data["radar"]["max_range_m"]
        brake_m = v * 0.35 + v * v / (2 * 8.9)
        assert (brake_m > reveal_m) == (c.ego_speed_kmh >= 70), c.cell_id
        occupied = [o for o in data["objects"] if o["name"].startswith("adjacent")]
        assert len(occupied) == (3 if "occupied" in c.group else 0)


@pytest.mark.parametrize("collided, departure, passed", [(False, 0.0, True), (True, 0.0, False),
                                                          (False, 0.01, False)])
def test_emergency_steering_fails_on_contact_or_leaving_the_road(collided, departure, passed):
    row = score_cell("emergency_steering", {}, outcome(collided, 20.0 if collided else 0.0, 1, departure))
    assert row["passed"] is passed


def test_layout_errors_name_the_key(tmp_path):
    head = ('[catalogue]\nscoring = "ncap_fc"\n[sources]\nx = "y"\n[targets.a]\nlength_m = 0.6\nwidth_m = 0.5\n'
            'source = "x"\n[[series]]\ngroup = "CPNA-50"\ntarget = "a"\nego_speed_kmh = [10, 20]\nsource = "x"\n')
    for body, fragment in (
            ('scene = "crossing"\n[series.layout]\nimpact_pct = 50\n', "series[0].layout.side: missing"),
            ('scene = "along"\n[series.layout]\nimpact_pct = 50\nspeed = 3\n', "series[0].layout.speed: unknown key"),
            ('scene = "along"\n[series.layout]\nimpact_pct = [50]\n', "series[0].layout.impact_pct: expected 2 values"),
            ('[series.layout]\nimpact_pct = 50\n', "series[0].layout: is read only by a planar scene"),
            ('scene = "crosing"\n', "series[0].scene: expected one of")):
        path = tmp_path / "bad.toml"
        path.write_text(head + body)
        with pytest.raises(ConfigError) as err:
            load_catalogue(path)
        assert str(err.value).startswith(f"{path}: ") and fragment in str(err.value), str(err.value)


# -- representative closed-loop runs ----------------------------------------------------------------------
@pytest.mark.slow
def test_representative_planar_cells_run_and_fail_with_a_thumbnail(tmp_path):
    """A kerb stop draws no intervention; a late stationary car at 100 km/h with the next lane occupied is hit
    (braking cannot stop within 42 m, and no steering path may enter the occupied lane: the ECU brakes in lane),
    on the road, and its report shows the failing cell's thumbnail. With the next lane free the ECU changes
    lanes and avoids it (round 33), so that cell passes and has no thumbnail."""
    from dataclasses import replace

    from cosim.matrix.report import write_outputs
    from cosim.matrix.runner import run_matrix

    fp = load_catalogue("planar_false_positive")
    es = load_catalogue("emergency_steering")
    cats = [replace(fp, cells=tuple(c for c in fp.cells if c.cell_id == "kerb-stop-40")),
            replace(es, cells=tuple(c for c in es.cells if c.cell_id in ("late-stationary-occupied-100",
                                                                          "late-stationary-free-100")))]
    rows, _ = run_matrix(cats, ["tightening"], phases=1, workers=1)
    kerb, free, late = sorted(rows, key=lambda r: (r["catalogue"] != "planar_false_positive", r["cell"]))
    assert free["cell"] == "late-stationary-free-100" and free["passed"] and not free["collided"]
    assert kerb["passed"] and kerb["interventions"] == 0 and not kerb["collided"]
    assert late["collided"] and late["hit_object"] == "stopped car" and late["road_departure_m"] == 0.0
    assert 0.0 < late["impact_kmh"] < 100.0 and not late["passed"]
    report = write_outputs(tmp_path, cats, rows, {"strategies": ["tightening"], "phases": 1, "runs": 2, "wall_s": 1.0,
                                                  "workers": 1, "version": "test"})
    thumb = tmp_path / "thumbs" / "emergency_steering_late-stationary-occupied-100.png"
    assert thumb.is_file() and f"(thumbs/{thumb.name})" in report.read_text()
    assert not (tmp_path / "thumbs" / "emergency_steering_late-stationary-free-100.png").exists()
    assert not list((tmp_path / "thumbs").glob("planar_false_positive_*"))
    assert "trace" not in (tmp_path / "matrix.json").read_text()


def test_radar_phase_moves_the_encounter_later_not_the_cars_at_the_egos_speed():
    v = 90 / 3.6
    cut = cells("emergency_steering")["cut-out-occupied-90"]
    a, b = cut.scenario_dict(0, 2), cut.scenario_dict(1, 2)
    stopped = {d["objects"][1]["position_m"] for d in (a, b)}
    assert max(stopped) - min(stopped) == pytest.approx(v * 0.025)  # half of one 50 ms radar update
    assert a["objects"][0]["trajectory"]["waypoints"][0] == b["objects"][0]["trajectory"]["waypoints"][0]
    assert [o["position_m"] for o in a["objects"][2:]] == [o["position_m"] for o in b["objects"][2:]]
    cross = cells("ncap_vru")["CPNA-50-40"]
    xs = [cross.scenario_dict(i, 2)["objects"][0]["crossing"]["x_m"] for i in range(2)]
    assert xs[1] - xs[0] == pytest.approx(40 / 3.6 * 0.025)


def test_fc_summary_counts_errored_cells_and_keeps_the_whole_maximum():
    from cosim.matrix.scorings import scoring_named

    table = load_catalogue("ncap_vru").scoring_table
    rows = [{"group": "CPNA-50", "colour": "green", "strategy": "s"}, {"group": "CBNA-50", "strategy": "s"}]
    text = scoring_named("ncap_fc").summary(rows, table)
    assert "NCAP 0.50/11.75 pts (CPNA 0.50)" in text and "1 cells errored (not scored)" in text
