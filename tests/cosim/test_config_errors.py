"""One error format for every configuration file kind: ``<file>: <key.path>: <problem>[; did you mean <x>?]``.

For each kind (scenario, standalone ECU file, catalogue, sweep): an unknown key with its suggestion,
a value of the wrong type and one out of range, each one line naming the file and the key path, with
the expected and the actual value.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from cosim.errors import ConfigError
from cosim.matrix.catalogue import load_catalogue
from cosim.scenarios.loader import load_scenario
from cosim.sweep.spec import load_sweep
from ecu import EcuConfig

DATA = Path(__file__).resolve().parent / "sweep_data"
_CATALOGUE = ('[catalogue]\nscoring = "r152"\n[sources]\nx = "y"\n[targets.car]\nlength_m = 4.0\nwidth_m = 1.7\n'
              'source = "x"\n[[series]]\ngroup = "g"\nego_speed_kmh = [10]\nmax_impact_kmh = 0\ntarget = "car"\n'
              'source = "x"\n')
_SWEEP = f'[sweep]\nscenario = "{DATA / "short_cyclist.toml"}"\n[[axis]]\npath = "radar.latency_s"\nvalues = [0.1]\n'

KINDS = {
    "scenario": (load_scenario, "[radar]\nlatency_s = 0.1\n"),
    "ecu": (EcuConfig.from_toml, "[ecu]\nstrategy = \"none\"\n"),
    "catalogue": (load_catalogue, _CATALOGUE),
    "sweep": (load_sweep, _SWEEP),
}
CASES = [  # kind, text appended to the valid file (TOML: a later table or key), expected "<key.path>: <problem>"
    ("scenario", "[plant]\nroad_fricton = 0.5\n", "plant.road_fricton: unknown key; did you mean plant.road_friction?"),
    ("scenario", "[plant]\nroad_friction = \"wet\"\n", "plant.road_friction: expected a number, got 'wet'"),
    ("scenario", "[plant]\nroad_friction = 2.0\n", "plant.road_friction: expected a value in [0, 1.5], got 2.0"),
    ("ecu", "standof_m = 3.0\n", "ecu.standof_m: unknown key; did you mean ecu.standoff_m?"),
    ("ecu", "abs_slip_cycles = 2.5\n", "ecu.abs_slip_cycles: expected an integer, got 2.5"),
    ("ecu", "peak_decel_mps2 = 16.0\n", "ecu.peak_decel_mps2: expected a value in (0, 15] m/s^2, got 16.0"),
    ("catalogue", "settle = 2.0\n", "series[0].settle: unknown key; did you mean series[0].settle_s?"),
    ("catalogue", "extended = 1\n", "series[0].extended: expected true or false, got 1"),
    ("catalogue", "road_friction = 1.6\n", "series[0].road_friction: expected a value in [0, 1.5], got 1.6"),
    ("sweep", "distribuion = \"uniform\"\n", "axis[0].distribuion: unknown key; did you mean axis[0].distribution?"),
    ("sweep", "cross = \"yes\"\n", "axis[0].cross: expected true or false, got 'yes'"),
    ("sweep", "std = -1.0\n", "axis[0].std: expected a value in (0, inf), got -1.0"),
    ("sweep", "[sweep.x]\n", "sweep.x: unknown key; expected one of scenario, fleet, name, description, mode, seed, "
                             "samples, latin_hypercube, replicates"),
]
_FORMAT = re.compile(r"^(?P<file>[^:]+\.toml): (?P<key>[\w.\[\]]+): (?P<problem>[^\n]+)$")


@pytest.mark.parametrize("kind, extra, expected", CASES, ids=[f"{c[0]}-{c[2].split(':')[0]}" for c in CASES])
def test_one_format_for_every_file_kind(tmp_path, kind, extra, expected):
    loader, valid = KINDS[kind]
    path = tmp_path / f"{kind}.toml"
    path.write_text(valid)
    loader(path)  # the valid file loads
    path.write_text(valid + extra)
    with pytest.raises(ConfigError) as err:
        loader(path)
    message = str(err.value)
    match = _FORMAT.match(message)
    assert match is not None, message
    assert match["file"] == str(path) and message == f"{path}: {expected}"


def test_each_kind_covers_unknown_type_and_range():
    for kind in KINDS:
        problems = [c[2] for c in CASES if c[0] == kind]
        assert any("unknown key; did you mean" in p for p in problems), kind
        assert any(re.search(r"expected (a number|an integer|true or false), got", p) for p in problems), kind
        assert any("expected a value in" in p for p in problems), kind


def test_sweep_range_and_catalogue_scoring_errors(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(_SWEEP.replace('[sweep]\n', '[sweep]\nreplicates = 0\n'))
    with pytest.raises(ConfigError, match=rf"^{re.escape(str(path))}: sweep\.replicates: expected a value in "
                                          r"\[1, 9223372036854775807\], got 0$"):
        load_sweep(path)
    cat = tmp_path / "c.toml"
    cat.write_text(_CATALOGUE.replace('scoring = "r152"', 'scoring = "r125"'))
    with pytest.raises(ConfigError, match=r"c\.toml: catalogue\.scoring: expected one of \['r152', 'ncap', "
                                          r"'false_positive', 'follow', 'ncap_fc', 'emergency_steering'\], got 'r125'; "
                                              r"did you mean 'r152'\?$"):
        load_catalogue(cat)
    cat.write_text(_CATALOGUE.replace("max_impact_kmh = 0\n", ""))
    with pytest.raises(ConfigError, match=r"c\.toml: series\[0\]\.max_impact_kmh: missing; expected a number$"):
        load_catalogue(cat)  # r152 needs the limit of every cell
    cat.write_text(_CATALOGUE + "lateral_end_m = 3.5\nlateral_speed_mps = 1.0\n")
    with pytest.raises(ConfigError, match=r"c\.toml: series\[0\]\.lateral_at_gap_m: missing; expected a number$"):
        load_catalogue(cat)  # a lateral motion needs its trigger
