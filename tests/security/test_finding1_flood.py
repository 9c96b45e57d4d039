"""Finding 1: valid-CRC WheelSpeeds at 0 km/h flooded into the loop blinded the ECU.

Before issue 15: at 10,000 frames/s the ECU stayed in STANDBY and the car hit the
cyclist at full throttle; at one forged frame per cycle it went to FAULT, cut
the throttle without braking and coasted into the cyclist. Now the receiver
invalidates the wheel speeds within 100 ms of the onset (the flood by frequency
monitoring, the one-per-cycle forger by its counters interleaving with the
genuine ones) and the degraded mode brakes from the radar's closing speed
(ecu/core/degraded.py).
Onset at 9 s: 28 m/s, 91 m from the cyclist.
"""

import pytest

from can_dbc import CounterSequence
from ecu.core import FaultFlag

from .attacks import attacked_run, wheel_frames

ONSET_S = 9.0
pytestmark = pytest.mark.slow


def _flood(per_cycle):
    counters = CounterSequence()
    return lambda t_s, cycle: wheel_frames(0.0, counters, per_cycle) if t_s >= ONSET_S - 1e-9 else []


@pytest.mark.parametrize("per_cycle", [100, 1], ids=["10000_per_s", "1_per_cycle"])
def test_wheel_speed_flood_does_not_blind_the_ecu_keyless(plant_fmu3, per_cycle):
    """E2E only (no key): the receiver checks of part 1 alone must hold."""
    flagged, degraded_braking = [], []
    def watch(t_s, out):
        if out is not None and out.mode.name == "FAULT" and out.brake_decel_request_mps2 > 0.0:
            degraded_braking.append(t_s)
        # the flood is too fast; one forged frame per cycle interleaves its counters with the genuine ones
        names = ("RATE", "SEQUENCE") if per_cycle > 1 else ("SEQUENCE",)
        mask = sum(1 << getattr(FaultFlag, n) for n in names if hasattr(FaultFlag, n))  # (absent before issue 15)
        if out is not None and t_s >= ONSET_S - 1e-9 and out.fault_flags & mask:
            flagged.append(t_s)
    rec = attacked_run(plant_fmu3, "tightening", authenticate=False, to_ecu=_flood(per_cycle), watch=watch)
    assert not rec.metrics.collided, f"collided at {rec.metrics.impact_speed_mps} m/s"
    assert rec.metrics.final_gap_m >= 2.0  # the standoff (measured: 7.0 m)
    assert degraded_braking  # stopped by the degraded mode's braking, not by coasting
    assert flagged and flagged[0] - ONSET_S <= 0.1 + 1e-9  # flood detected within 100 ms of its onset


def test_wheel_speed_flood_with_authentication(plant_fmu3):
    """With SecOC every forged frame is rejected; the genuine ones are displaced, so the wheels time out."""
    rec = attacked_run(plant_fmu3, "tightening", authenticate=True, to_ecu=_flood(100))
    assert not rec.metrics.collided, f"collided at {rec.metrics.impact_speed_mps} m/s"
    assert any(e.kind == "ecu_security_fault" for e in rec.events)
