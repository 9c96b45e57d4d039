"""Protocol rules of the bundled catalogues and of the scoring: one test per rule that could be wrong."""

import pytest

from cosim.errors import ConfigError
from cosim.matrix.catalogue import bundled, load_catalogue
from cosim.matrix.scoring import Outcome, interventions, worst
from cosim.matrix.scorings import score_cell
from cosim.matrix.scorings.ncap import ncap_colour, ncap_points
from cosim.scenarios.loader import scenario_from_dict


def cells(name):
    return {c.cell_id: c for c in load_catalogue(name).cells}


def outcome(impact_kmh=0.0, collided=None, n=0, low=None):
    hit = impact_kmh > 0.0 if collided is None else collided
    return Outcome(hit, impact_kmh, n, low, None, None, 1.0, 0.1)


# -- Euro NCAP colour bands (worked example, v1.1) -----------------------------------------------
@pytest.mark.parametrize("impact, collided, colour, score", [
    (0.0, False, "green", 1.0), (0.01, True, "yellow", 0.75), (10.0, True, "yellow", 0.75),
    (10.01, True, "orange", 0.5), (20.0, True, "orange", 0.5), (20.01, True, "brown", 0.25),
    (30.0, True, "brown", 0.25), (30.01, True, "red", 0.0)])
def test_ncap_colour_band_edges(impact, collided, colour, score):
    assert ncap_colour(impact, collided) == (colour, score)


def test_ncap_extended_cell_scores_one_unless_red():
    assert score_cell("ncap", {"extended": True}, outcome(25.0))["score"] == 1.0
    assert score_cell("ncap", {"extended": True}, outcome(31.0))["score"] == 0.0


def test_ncap_points_are_the_protocols_and_average_over_cells():
    points = load_catalogue("ncap_ccr").scoring_table.points
    assert points == {"CCRs": 1.2, "CCRm": 2.4, "CCRb": 1.6, "CBLA": 2.0}
    rows = [{"strategy": "s", "group": "CCRs", "score": s} for s in (1.0, 0.5)]
    assert ncap_points(rows, points)["s"] == {"CCRs": pytest.approx(0.9), "total": pytest.approx(0.9)}


def test_ccrs_speeds_and_avoidance_requirement_up_to_20_kmh():
    c = cells("ncap_ccr")
    ccrs = [x for x in c.values() if x.group == "CCRs"]
    assert [x.ego_speed_kmh for x in ccrs] == [10, 20, 30, 40, 50, 60, 70, 80]
    assert [x.ego_speed_kmh for x in ccrs if x.get("require_no_contact")] == [10, 20]
    assert not score_cell("ncap", c["CCRs-20"].params, outcome(0.5))["passed"]
    assert score_cell("ncap", c["CCRs-30"].params, outcome(0.5))["passed"]
    assert all(x.get("target_speed_kmh") == 0 and x.target["length_m"] == 4.023 for x in ccrs)


def test_ccrm_ccrb_cbla_parameters():
    c = cells("ncap_ccr")
    assert [x.ego_speed_kmh for x in c.values() if x.group == "CCRm"] == [30, 40, 50, 60, 70, 80]
    assert {x.get("target_speed_kmh") for x in c.values() if x.group == "CCRm"} == {20}
    ccrb = [x for x in c.values() if x.group == "CCRb"]
    assert [x.ego_speed_kmh for x in ccrb] == list(range(30, 140, 10))
    assert all(x.get("target_speed_kmh") == x.ego_speed_kmh and x.get("headway_s") == 1.0
               and x.get("brake_decel_mps2") == 4.0 and x.get("brake_ramp_s") == 1.0 for x in ccrb)
    cbla = [x for x in c.values() if x.group == "CBLA"]
    assert [x.ego_speed_kmh for x in cbla] == [20, 30, 40, 50, 60]
    assert all(x.get("target_speed_kmh") == 15 and (x.target["length_m"], x.target["width_m"]) == (1.89, 0.5)
               for x in cbla)


# -- UN R152 ------------------------------------------------------------------------------------------
def test_r152_limits_are_the_m1_table():
    c = cells("r152_m1")
    limits = {x.ego_speed_kmh: x.get("max_impact_kmh") for x in c.values() if x.group == "R152-stationary"}
    assert limits == {10: 0, 20: 0, 30: 0, 40: 0, 42: 0, 45: 15, 50: 25, 55: 30, 60: 35}
    moving = [x for x in c.values() if x.group == "R152-moving"]
    assert {x.get("target_speed_kmh") for x in moving} == {20}
    assert all(x.get("max_impact_kmh") == 0 for x in moving)  # relative speed 10..40 km/h: no impact


@pytest.mark.parametrize("limit, impact, passed", [(15, 15.0, True), (15, 15.01, False), (0, 0.01, False),
                                                   (0, 0.0, True), (35, 34.9, True)])
def test_r152_pass_is_impact_at_most_the_limit(limit, impact, passed):
    assert score_cell("r152", {"max_impact_kmh": limit}, outcome(impact))["passed"] is passed


@pytest.mark.parametrize("name, mu", [("r152_m1_mu07", 0.7), ("r152_m1_mu05", 0.5), ("r152_m1", 1.0)])
def test_wet_extensions_keep_the_r152_limits_on_another_friction(name, mu):
    dry, wet = cells("r152_m1"), load_catalogue(name).cells
    assert all(c.get("road_friction") == mu for c in wet)
    assert sorted(c.get("max_impact_kmh") for c in wet) == sorted(c.get("max_impact_kmh") for c in dry.values())


# -- false positives and following ---------------------------------------------------------------------
def test_interventions_count_restricting_modes_after_start_up_only():
    assert interventions(["FAULT"] * 9 + ["STANDBY"] * 5) == 0
    assert interventions(["FAULT", "STANDBY", "TIGHTENING", "TIGHTENING", "STANDBY", "CONTINGENCY",
                          "TIGHTENING", "STANDBY"]) == 3
    assert interventions(["FAULT", "STANDBY", "FAULT", "STANDBY"]) == 1  # a fault limits the throttle too
    assert not score_cell("false_positive", {}, outcome(n=1))["passed"]
    assert score_cell("false_positive", {}, outcome(n=0))["passed"]


def test_false_positive_catalogue_geometry():
    c = cells("false_positive")
    assert {c[f"follow-{h}s-50"].get("headway_s") for h in (1, 2)} == {1.0, 2.0}
    assert c["adjacent-stationary-car-50"].get("lateral_m") == 3.5
    # 1.5 m between our side (1.815/2) and the bicycle's (0.50/2)
    assert c["pass-cyclist-1.5m-50"].get("lateral_m") - 1.815 / 2 - 0.25 == pytest.approx(1.5)


def test_follow_fails_on_a_standstill():
    assert not score_cell("follow", {}, outcome(low=0.05))["passed"]
    assert score_cell("follow", {}, outcome(low=3.0))["passed"]


def test_worst_phase_is_scored():
    phases = [outcome(0.0), outcome(6.3), outcome(2.0)]
    assert worst(phases).impact_kmh == 6.3
    assert worst([outcome(n=0), outcome(n=2)]).interventions == 2


# -- the format ---------------------------------------------------------------------------------------
def test_every_bundled_cell_is_a_valid_scenario_and_phases_shift_the_encounter():
    for name in bundled():
        for cell in load_catalogue(name).cells:
            scenario_from_dict(cell.scenario_dict(0, 3))
    ccrs50 = cells("ncap_ccr")["CCRs-50"]
    gaps = [ccrs50.scenario_dict(i, 3)["objects"][0]["position_m"] for i in range(3)]
    v = 50 / 3.6
    assert gaps[0] == pytest.approx(v * (2.0 + 4.0))  # 2 s settling, then TTC 4 s
    assert gaps[2] - gaps[0] == pytest.approx(v * 0.05 * 2 / 3)  # two thirds of one 50 ms radar update
    ccrb = cells("ncap_ccr")["CCRb-50"].scenario_dict(1, 2)["objects"][0]
    assert ccrb["position_m"] == pytest.approx(v * 1.0) and ccrb["brake_at_s"] == pytest.approx(2.025)


@pytest.mark.parametrize("text, fragment", [
    ('[catalogue]\nscoring = "r152"\n[sources]\nx = "y"\n[targets]\n[[series]]\ngroup = "g"\n'
     'ego_speed_kmh = [10]\ntarget = "car"\nsource = "x"\nspeed = 3\n', "series[0].speed: unknown key; did you mean series[0].scene?"),
    ('[catalogue]\nscoring = "ncap"\n[sources]\nx = "y"\n[targets.car]\nlength_m = 4.0\nwidth_m = 1.7\n'
     'source = "nope"\n[[series]]\n', "targets.car.source: unknown source 'nope'"),
    ('[catalogue]\nscoring = "r152"\n[sources]\nx = "y"\n[targets.car]\nlength_m = 4.0\nwidth_m = 1.7\n'
     'source = "x"\n[[series]]\ngroup = "g"\nego_speed_kmh = [10, 20]\nmax_impact_kmh = [0]\ntarget = "car"\n'
     'source = "x"\n', "series[0].max_impact_kmh: expected 2 values"),
    ('[catalogue]\nscoring = "euro"\n', "catalogue.scoring: expected one of ['r152', 'ncap', 'false_positive', 'follow', 'ncap_fc', 'emergency_steering'], got 'euro'"),
    ('[catalogue]\nscoring = "ncapp"\n', "catalogue.scoring: expected one of ['r152', 'ncap', 'false_positive', 'follow', 'ncap_fc', 'emergency_steering'], got 'ncapp'; did you mean 'ncap'?"),
])
def test_catalogue_errors_name_the_file_and_key(tmp_path, text, fragment):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ConfigError) as err:
        load_catalogue(path)
    assert str(err.value).startswith(f"{path}: ") and fragment in str(err.value)


def test_low_speed_counts_while_the_ecu_intervenes_not_the_drivers_later_coasting():
    from cosim.matrix.runner import _low_speed_while_intervening as low
    modes = ["FAULT", "STANDBY", "CONTINGENCY", "CONTINGENCY", "STANDBY", "STANDBY", "STANDBY"]
    speeds = [10.0, 10.0, 9.0, 6.0, 4.0, 3.0, 0.5]
    assert low(modes, speeds, after_cycles=2) == 3.0
    assert low(modes, speeds, after_cycles=100) == 0.5
    assert low(["STANDBY"] * 3, [1.0, 0.0, 0.0]) is None


def test_cell_values_are_type_checked(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('[catalogue]\nscoring = "r152"\n[sources]\nx = "y"\n[targets.car]\nlength_m = 4.0\n'
                    'width_m = 1.7\nsource = "x"\n[[series]]\ngroup = "g"\nego_speed_kmh = [10, -5]\n'
                    'max_impact_kmh = 0\ntarget = "car"\nsource = "x"\n')
    with pytest.raises(ConfigError, match=r"bad.toml: series\[0\].ego_speed_kmh\[1\]: expected a value in \[0, 300\] km/h, got -5$"):
        load_catalogue(path)


def test_scorings_are_a_registry_and_an_unknown_name_is_an_error():
    from cosim.errors import ConfigError as Error
    from cosim.matrix.catalogue import CatalogueHead
    from cosim.matrix.scorings import SCORINGS
    from ecu.settings import keys

    assert all(name == s.name for name, s in SCORINGS.items())
    assert keys(CatalogueHead)["scoring"].declared.choices == tuple(SCORINGS)  # the catalogue key offers the table
    assert {load_catalogue(n).scoring for n in bundled()} == set(SCORINGS)  # every scoring is used
    with pytest.raises(Error, match=r"^catalogue\.scoring: expected one of \[.*\], got 'folow'; did you mean 'follow'\?$"):
        score_cell("folow", {}, outcome(low=3.0))  # once fell through to follow's rule
