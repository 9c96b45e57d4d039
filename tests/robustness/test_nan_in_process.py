"""Finding 6 of issue 15, in process: a NaN plant output is an error naming the time and the FMU variable.

Before, the NaN reached the CAN encoder (``error: ObjectTrack.ObjectRange: expected a finite
value, got nan``): no time, no FMU variable, and nothing written.
"""

from __future__ import annotations

import json

from cosim.cli.main import main
from cosim.loop.master import ClosedLoop

from .test_isolated_plant import _scenario


def test_nan_output_of_an_in_process_plant_names_the_time_and_the_variable(faulty_fmu):
    record = ClosedLoop(_scenario(4, isolation="inprocess"), faulty_fmu, "tightening").run()
    assert record.error is not None
    assert "'v_mps'" in record.error and "nan" in record.error and "t = 1.0" in record.error
    assert record.status == "error"
    assert len(record.rows) >= 100 and 0.99 <= record.rows[-1][0] <= 1.01  # the results up to the NaN are kept
    assert [e.kind for e in record.events if e.kind == "fmi_error"] == ["fmi_error"]


def test_crd_run_on_a_nan_output_writes_the_results_so_far_and_exits_1(faulty_fmu, tmp_path, capsys):
    scenario = tmp_path / "nan.toml"
    scenario.write_text(f"""
[scenario]
duration_s = 3.0
step_s = 0.01
[plant]
fmu = "{faulty_fmu}"
isolation = "inprocess"
parameters = {{ fault = 4, fault_at = 1.0 }}
inputs = {{ accel_command = "a_cmd" }}
outputs = {{ position = "s_m", speed = "v_mps" }}
[object]
position_m = 500.0
""")
    out = tmp_path / "out"
    assert main(["run", str(scenario), "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("error: ") and "'v_mps'" in err and "t = 1.0" in err
    metrics = json.loads((out / "metrics.json").read_text())
    assert metrics["status"] == "error"
    assert metrics["runs"][0]["status"] == "error" and "'v_mps'" in metrics["runs"][0]["error"]
    rows = (out / "tightening" / "timeseries.csv").read_text().splitlines()
    assert len(rows) >= 101 and float(rows[-1].split(",")[0]) >= 0.99
