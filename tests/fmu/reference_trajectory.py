"""The plant's trajectory under the ``dance`` schedule as the 1 ms-only FMU computed it.

``tests/fmu/data/dance_reference.json`` was written by this module (``python -m
tests.fmu.reference_trajectory``) from the FMI 2 build of commit aaef959, the last plant
that accepted only whole multiples of 1 ms per ``doStep``. It holds every output every
50 ms for 6 s as exact hexadecimal floats, so tests can check that the variable-step
plant still produces that trajectory bit for bit on the 1 ms grid.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from tests.fmu.plant_runner import OUTPUTS, run_plant
from tests.fmu.test_integration import dance

REFERENCE_PATH = Path(__file__).resolve().parent / "data" / "dance_reference.json"
STOP_S = 6.0
STRIDE_S = 0.05


def load_reference() -> dict[str, np.ndarray]:
    """The stored trajectory: arrays keyed "t" and each output, one row per 50 ms."""
    raw = json.loads(REFERENCE_PATH.read_text())
    return {name: np.array([float.fromhex(x) for x in raw[name]]) for name in ("t", *OUTPUTS)}


def main() -> None:
    from fmu_plant.build import ensure_fmu

    run = run_plant(ensure_fmu(fmi_version=2), 2, STOP_S, 0.001, dance)
    stride = round(STRIDE_S / 0.001)
    data = {name: [float(x).hex() for x in run[name][::stride]] for name in ("t", *OUTPUTS)}
    REFERENCE_PATH.write_text(json.dumps(data, indent=0) + "\n")


if __name__ == "__main__":
    main()
