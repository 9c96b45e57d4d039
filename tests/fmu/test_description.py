"""Model descriptions: fmpy validation, agreement with the C table, build and cache."""

import re
import zipfile

import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

from fmu_plant import build
from fmu_plant.description import UNIT_BASES
from fmu_plant.variables import VARIABLES, TABLE_PATH

CONTRACT_NAMES = {"throttle", "brake", "road_friction", "grade", "x", "v", "a", "wheel_speed_fl",
                  "wheel_speed_fr", "wheel_speed_rl", "wheel_speed_rr", "brake_pressure",
                  "drive_force", "mass", "wheel_radius", "v0", "x0", "abs_enabled",
                  "brake_dead_time", "brake_time_constant", "throttle_time_constant"}
#: value references importers rely on: those of the longitudinal plant (d2cf42d) never change,
#: the planar ones (issue 21) are appended
PINNED_VRS = {
    "time": 0, "throttle": 1, "brake": 2, "road_friction": 3, "grade": 4, "x": 10, "v": 11, "a": 12,
    "wheel_speed_fl": 13, "wheel_speed_fr": 14, "wheel_speed_rl": 15, "wheel_speed_rr": 16,
    "brake_pressure": 17, "drive_force": 18, "mass": 30, "wheel_radius": 31, "v0": 32, "x0": 33,
    "abs_enabled": 34, "brake_dead_time": 35, "brake_time_constant": 36, "throttle_time_constant": 37,
    "drag_area": 38, "air_density": 39, "rolling_resistance": 40, "max_power": 41, "max_drive_force": 42,
    "drive_front_share": 43, "max_brake_force": 44, "brake_front_share": 45, "cg_to_front_axle": 46,
    "wheelbase": 47, "cg_height": 48, "wheel_inertia": 49, "tyre_B": 50, "tyre_C": 51, "tyre_D": 52,
    "tyre_E": 53, "abs_slip_release": 54, "abs_slip_reapply": 55, "brake_release_dead_time_fraction": 56,
    "brake_release_time_constant_fraction": 57,
    # planar (issue 21)
    "steering_wheel_angle": 5, "steer_request": 6, "y": 19, "yaw": 20, "yaw_rate": 21, "ay": 22, "vx": 23,
    "vy": 24, "delta": 25, "ax": 26, "yaw_inertia": 58, "tyre_cornering_stiffness": 59, "tyre_lateral_C": 60,
    "tyre_lateral_E": 61, "steering_ratio": 62, "steering_time_constant": 63, "steering_angle_max": 64,
    "steering_rate_max": 65, "y0": 66, "yaw0": 67, "tyre_lateral_D": 68,
}


@pytest.mark.parametrize("version", [2, 3])
def test_fmpy_validation_passes(fmus, version):
    assert validate_fmu(str(fmus[version])) == []
    md = read_model_description(str(fmus[version]), validate=True)
    assert md.fmiVersion == f"{version}.0"
    assert md.coSimulation is not None and md.modelExchange is None


@pytest.mark.parametrize("version", [2, 3])
def test_description_matches_the_c_table(fmus, version):
    md = read_model_description(str(fmus[version]))
    got = {v.name: (v.valueReference, v.causality) for v in md.modelVariables}
    causality = {"INDEPENDENT": "independent", "INPUT": "input", "OUTPUT": "output", "PARAMETER": "parameter"}
    assert got == {v.name: (v.vr, causality[v.kind]) for v in VARIABLES}
    assert CONTRACT_NAMES <= set(got)
    for var in md.modelVariables:
        if var.type in ("Real", "Float64"):
            assert var.unit in UNIT_BASES, f"{var.name} declares no known unit: {var.unit!r}"


def test_value_references_are_pinned():
    assert {v.name: v.vr for v in VARIABLES} == PINNED_VRS


def test_table_parses_every_entry_line():
    entries = [line for line in TABLE_PATH.read_text().splitlines() if line.startswith("PLANT_VAR(")]
    assert len(entries) == len(VARIABLES) > 30


def test_the_c_side_uses_the_same_table():
    src = (TABLE_PATH.parent / "variables.h").read_text() + (TABLE_PATH.parent / "variables.c").read_text()
    assert len(re.findall(r"#include \"variables.def\"", src)) == 4  # struct, table, index enum, vr map


def test_ensure_fmu_caches_by_source_hash(fmus, tmp_path):
    first = build.ensure_fmu(2, cache_dir=tmp_path)
    mtime = first.stat().st_mtime_ns
    again = build.ensure_fmu(2, cache_dir=tmp_path)
    assert again == first and again.stat().st_mtime_ns == mtime
    assert build.source_hash(2)[:20] in first.parent.name
    assert build.source_hash(2) != build.source_hash(3)
    assert [p.name for p in tmp_path.iterdir()] == [first.parent.name]  # no staging left over


def test_two_processes_building_at_once_agree(tmp_path):
    import subprocess
    import sys

    code = "import sys; from fmu_plant.build import ensure_fmu; print(ensure_fmu(2, cache_dir=sys.argv[1]))"
    procs = [subprocess.Popen([sys.executable, "-c", code, str(tmp_path)], stdout=subprocess.PIPE, text=True)
             for _ in range(2)]
    paths = {p.communicate(timeout=120)[0].strip() for p in procs}
    assert [p.returncode for p in procs] == [0, 0]
    assert len(paths) == 1 and validate_fmu(paths.pop()) == []
    assert len(list(tmp_path.iterdir())) == 1  # the loser's staging directory is gone


def test_build_fmu_writes_a_complete_fmu(tmp_path):
    out = build.build_fmu(3, tmp_path / "sub" / "plant.fmu")
    names = set(zipfile.ZipFile(out).namelist())
    assert "modelDescription.xml" in names
    assert any(n.startswith("binaries/") and n.endswith("/vehicle_plant.so") for n in names)


def test_missing_cmake_is_a_typed_error(monkeypatch, tmp_path):
    monkeypatch.setattr(build.shutil, "which", lambda name: None)
    with pytest.raises(build.ToolchainMissingError, match="cmake"):
        build.build_fmu(2, tmp_path / "x.fmu")
    assert not (tmp_path / "x.fmu").exists()


def test_failed_command_reports_output_tail():
    with pytest.raises(build.CompileError, match="(?s)exit code 3.*boom"):
        build._run(["sh", "-c", "echo boom; exit 3"], "test step")


def test_bad_fmi_version_is_refused():
    with pytest.raises(ValueError, match="2 or 3, got 4"):
        build.ensure_fmu(4)


def test_cli_builds_and_prints_the_path(tmp_path, capsys):
    from cosim.cli.main import main

    out = tmp_path / "p.fmu"
    assert main(["fmu", "build", "--fmi-version", "3", "--out", str(out)]) == 0
    assert capsys.readouterr().out.strip() == str(out.resolve())
    assert validate_fmu(str(out)) == []
