"""With the wheel straight the plant is today's longitudinal plant, bit for bit.

Golden data: ``tests/fmu/data/longitudinal_golden.json``, recorded from the longitudinal-only
plant of commit d2cf42d before the plant became planar (``golden_longitudinal.py``). Each
sequence runs in both FMI versions with the steering inputs held at 0 at every communication
point, and every output at every point must equal the recording exactly (the SHA-256 over all
points; the stored rows show where a difference starts).
"""

import numpy as np
import pytest

from tests.fmu.golden_longitudinal import SEQUENCES, digest, load_golden, run_sequence, stride
from tests.fmu.plant_runner import OUTPUTS

#: the steering inputs, held straight
STRAIGHT = {"steering_wheel_angle": 0.0, "steer_request": 0.0}


@pytest.mark.parametrize("version", [2, 3])
@pytest.mark.parametrize("name", sorted(SEQUENCES))
def test_straight_wheel_reproduces_the_longitudinal_plant_bit_for_bit(fmus, version, name):
    golden = load_golden()[name]
    seq = SEQUENCES[name]
    run = run_sequence(fmus[version], version, seq, STRAIGHT)
    assert len(run["t"]) == golden["rows"] and stride(seq) == golden["stride"]
    k = golden["stride"]
    for col in ("t", *OUTPUTS):
        expect = np.array([float.fromhex(x) for x in golden[col]])
        np.testing.assert_array_equal(run[col][::k], expect, err_msg=f"{name}: {col}")
    assert digest(run) == golden["sha256"], f"{name}: an output differs between the stored rows"


def test_the_golden_sequences_exercise_what_they_claim():
    """The recording covers driving, ABS cycling, locked wheels and standstill."""
    golden = load_golden()
    v = {name: np.array([float.fromhex(x) for x in g["v"]]) for name, g in golden.items()}
    assert v["full_throttle"].max() > 100 / 3.6
    assert v["abs_braking_dry"][-1] == 0.0 and v["abs_braking_dry"][0] > 27.0
    locked = np.array([float.fromhex(x) for x in golden["locked_wheels_on_slopes_rear_drive"]["wheel_speed_fl"]])
    assert (locked == 0.0).any()
    assert len(set(np.diff(SEQUENCES["random_inputs_random_steps"].points_us))) >= 6
