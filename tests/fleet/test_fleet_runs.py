"""Fleet runs: each car sees the others, the lock-step is deterministic, in process and with an ECU process
per car; the bundled scenes show the dance's collision and deadlock."""

import re

import can
import pytest

from cosim.cli.fleet import find_scene
from cosim.cli.main import main
from cosim.fleet.config import load_fleet
from cosim.fleet.output import run_fleet
from cosim.scenarios.loader import load_scenario

#: frames the ECU process link adds on each bus (its clock and its announcement), not the run's traffic
LINK_IDS = {0x7F0, 0x7F1, 0x3B0, 0x3B1}


def _speeds(record):
    i = record.columns.index("speed_mps")
    return [row[i] for row in record.rows]


def test_symmetric_crossing_both_cars_invoke_and_move_alike():
    record, dance = run_fleet(load_fleet(find_scene("crossing")), None, {"west": "none", "south": "none"})
    west, south = record.records
    assert _speeds(west) == _speeds(south)  # mirror images: each sees the other as it is seen
    assert west.metrics.contingency_invocations >= 2
    assert min(_speeds(west)) < 1.0  # each stops nearly, because of the other alone (no object in its scene)
    assert dance.first_contingency_s is not None


def test_four_way_deadlocks():
    record, dance = run_fleet(load_fleet(find_scene("four_way")), None)
    assert dance.collisions == 0
    assert dance.deadlock_s > 10.0
    assert dance.time_to_clear_s is None


def test_the_plain_method_collides_at_the_crossing():
    """The symmetric crossing under the plain contingency: both cars stop short of each other's stopping region,
    release as it shrinks, both robots accelerate, and they touch."""
    _, dance = run_fleet(load_fleet(find_scene("crossing")), None, {"west": "none", "south": "none"})
    assert dance.collisions == 2
    for car in dance.vehicles:
        assert car.contingency_invocations >= 2


def test_reacting_drivers_keep_the_pedal_down_and_the_plain_method_collides():
    """The crossing with human drivers (reaction times drawn per car), who keep the pedal down: each ECU invokes
    its contingency once the other's stopping region reaches its path, but that region assumes the other brakes
    now, while its driver still accelerates: both stop too late and touch (the two-axis separation test had
    counted the regions as touching earlier, by their bounding boxes, and both stood: a deadlock)."""
    record, dance = run_fleet(load_fleet(find_scene("crossing_reacting")), None, {"west": "none", "south": "none"})
    assert dance.collisions == 2
    pedal, mode = (record.records[0].columns.index(name) for name in ("accel_pedal_pct", "ecu_mode"))
    for car, metrics in zip(record.records, dance.vehicles):
        assert metrics.contingency_invocations == 1 and metrics.impact_speed_mps > 0.0
        first = next(row for row in car.rows if row[mode] == "CONTINGENCY")
        assert first[pedal] == 100.0  # the driver's pedal was down when his ECU invoked its contingency


def _frames(path):
    return [(m.timestamp, m.arbitration_id, bytes(m.data)) for m in can.BLFReader(path)
            if m.arbitration_id not in LINK_IDS]


def test_in_process_and_one_ecu_process_per_car_give_the_same_outputs(tmp_path):
    key = tmp_path / "k.key"
    key.write_text("00112233445566778899aabbccddeeff\n")
    key.chmod(0o600)
    outs = []
    for mode in ("inprocess", "process"):
        out = tmp_path / mode
        code = main(["fleet", "crossing_reacting", "--out", str(out), "--ecu", mode, "--key-file", str(key),
                     "--strategy", "none"])
        assert code == 3  # the plain method collides here
        outs.append(out)
    a, b = outs
    for name in ("world.csv", "west/timeseries.csv", "south/timeseries.csv", "west/events.json"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name
    for car in ("west", "south"):
        assert _frames(a / car / "can.blf") == _frames(b / car / "can.blf")
    assert (a / "speeds.png").is_file() and "| west |" in (a / "report.md").read_text()
    for seed, car in enumerate(("west", "south"), start=1):  # each car's run, resolved, reads as a scenario
        resolved = load_scenario(a / car / "config.resolved.toml")
        assert (resolved.scenario.seed, resolved.ecu.strategy) == (seed, "none")


def test_cli_refuses_a_bad_set_in_one_line(capsys):
    assert main(["fleet", "crossing", "--set", "east=none"]) == 1
    err = capsys.readouterr().err
    assert "--set east=none: no vehicle 'east'" in err and err.count("\n") == 1


def test_the_dance_is_visible_and_tightening_keeps_it_from_colliding():
    """Issue 23's first two figures: none collides (at the crossing, above, and with the reacting drivers);
    tightening dances at the crossing (>= 3 separate decelerations, recoveries >= 0.5 m/s, in both cars) and
    collides in neither."""
    fleet = load_fleet(find_scene("crossing"))
    _, plain = run_fleet(load_fleet(find_scene("crossing_reacting")), None, {"west": "none", "south": "none"})
    _, tight = run_fleet(fleet, None, {"west": "tightening", "south": "tightening"})
    _, reacting = run_fleet(load_fleet(find_scene("crossing_reacting")), None,
                            {"west": "tightening", "south": "tightening"})
    assert plain.collisions == 2
    assert tight.collisions == 0 and reacting.collisions == 0
    for car in tight.vehicles:
        assert car.decelerations >= 3 and min(car.recoveries_mps) >= 0.5


@pytest.mark.parametrize("scene", ["crossing", "crossing_reacting", "four_way", "merge", "narrow_passage"])
def test_right_of_way_clears_within_10_s_of_the_first_contingency(scene):
    _, dance = run_fleet(load_fleet(find_scene(scene), way_out="right_of_way"), None)
    assert dance.collisions == 0
    assert dance.all_cleared_s is not None and dance.time_to_clear_s <= 10.0


def _with_seed(scene: str, seed: int, tmp_path):
    path = tmp_path / f"{scene}_{seed}.toml"
    path.write_text(re.sub(r"^seed = \d+", f"seed = {seed}", find_scene(scene).read_text(), count=1, flags=re.M))
    return path


def test_the_exact_tie_at_a_narrowing_is_parted_by_the_patience_and_a_back_off(tmp_path):
    """Both cars reach the narrowing together and StVO section 6 gives neither the right to go: both wait (a
    standoff) until one's seeded patience runs out. With seed 2 (2.98 and 2.83 s) the other sees it go and lets
    it through. With seed 1 (2.89 and 2.98 s, closer than the time to see the other start) both go, see each
    other coming while taking their turn, back off and draw again (ecu.core.way_out): then one passes and the other
    follows. Both cleared within 10 s of the first
    contingency, without contact."""
    _, parted = run_fleet(load_fleet(_with_seed("narrow_passage_tie", 2, tmp_path), way_out="right_of_way"), None)
    assert parted.collisions == 0
    assert parted.all_cleared_s is not None and parted.time_to_clear_s <= 10.0
    _, tied = run_fleet(load_fleet(find_scene("narrow_passage_tie"), way_out="right_of_way"), None)
    assert tied.collisions == 0
    assert tied.all_cleared_s is not None and tied.time_to_clear_s <= 10.0


def test_the_merge_needs_the_corner_radars_and_the_ramp_car_merges_behind(tmp_path):
    """Without the rear corner radars neither car sees the other beside it until they touch; with them both
    clear, the car whose lane ends (ramp) after the one in the through lane (main)."""
    text = find_scene("merge").read_text()
    assert "corner = true" in text
    blind = tmp_path / "merge.toml"
    blind.write_text(text.replace("corner = true", "corner = false"))
    _, unseen = run_fleet(load_fleet(blind, way_out="right_of_way"), None)
    assert unseen.collisions > 0
    _, seen = run_fleet(load_fleet(find_scene("merge"), way_out="right_of_way"), None)
    cleared = {car.name: car.cleared_at_s for car in seen.vehicles}
    assert seen.collisions == 0 and cleared["main"] < cleared["ramp"]


def test_a_failing_plant_stops_the_scene_naming_the_vehicle_and_keeps_every_record(monkeypatch):
    """The FMU of one car fails at t = 1 s: the scene stops there, every car's record keeps its cycles so far,
    and the error names the car, the time and the cause."""
    from cosim.errors import FmiStepError
    from cosim.fleet.lockstep import FleetRun
    from cosim.loop.experiment import resolve_fmu

    fleet = load_fleet(find_scene("crossing"))
    run = FleetRun(fleet, {v.name: resolve_fmu(v.scenario) for v in fleet.vehicles})
    south = run.loops[1].plant
    real = south.step

    def failing(t_s, h_s):
        if t_s >= 1.0:
            raise FmiStepError(f"doStep failed at t = {t_s:.3f} s: fmi3Error", t_s, "fmi3Error")
        return real(t_s, h_s)

    monkeypatch.setattr(south, "step", failing)
    record = run.run()
    for r in record.records:
        assert r.error.startswith("south: doStep failed at t = 1.000 s") and r.rows
        assert abs(r.rows[-1][0] - 1.0) < 0.011
