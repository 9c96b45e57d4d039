"""``config.resolved.toml`` reads back as the same scenario, for every bundled scenario (planar ones too).

A planar object placed by ``pose``/``road_pose``/``trajectory``/``crossing`` must not carry the keys its
placement replaces (the loader refuses them): ``crd run --record`` and ``crd export`` re-read the file.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from cosim.scenarios.loader import load_scenario
from cosim.scenarios.resolve import scenario_to_dict, scenario_to_toml

BUNDLED = sorted((Path(__file__).resolve().parents[2] / "cosim" / "scenarios").glob("*.toml"))


@pytest.mark.parametrize("path", BUNDLED, ids=lambda p: p.stem)
def test_the_resolved_file_reads_back_as_the_same_scenario(tmp_path, path):
    scenario = load_scenario(path)
    resolved = tmp_path / "config.resolved.toml"
    resolved.write_text(scenario_to_toml(scenario))
    assert scenario_to_dict(load_scenario(resolved)) == scenario_to_dict(scenario)


def test_every_planar_bundled_scenario_is_covered():
    assert {"crossing_pedestrian", "curve_parked_car", "lane_change_parked_car"} <= {p.stem for p in BUNDLED}
