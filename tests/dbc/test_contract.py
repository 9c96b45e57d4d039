"""can_dbc.contract: timing, limits, names and units come from the DBC, and the rest of crd uses them."""

from __future__ import annotations

import cantools
import pytest

from can_dbc import DBC_PATH
from can_dbc.contract import (
    BRAKE_DECEL_MAX_MPS2, ECU_CYCLE_S, MODE_NAMES, STRATEGIES, STRATEGY_CODES, enumeration, signal_dbc_per_si,
    timeout_s,
)
from can_dbc.units import KMH_PER_MPS, dbc_per_si
from ecu import ConfigError as EcuConfigError, EcuConfig
from ecu.core import CoreParams, Mode

DB = cantools.database.load_file(str(DBC_PATH))


def _val(message: str, signal: str) -> dict[int, str]:
    return {int(k): str(v) for k, v in DB.get_message_by_name(message).get_signal_by_name(signal).choices.items()}


def test_cycle_times_and_timeouts_are_the_dbcs():
    assert ECU_CYCLE_S == DB.get_message_by_name("SafetyOverride").cycle_time / 1000
    assert timeout_s("WheelSpeeds") == 5 * DB.get_message_by_name("WheelSpeeds").cycle_time / 1000
    assert timeout_s("ObjectTrack") == 5 * DB.get_message_by_name("ObjectTrack").cycle_time / 1000
    p = CoreParams()
    assert (p.cycle_s, p.wheel_speeds_timeout_s, p.object_timeout_s) == (ECU_CYCLE_S, timeout_s("WheelSpeeds"),
                                                                         timeout_s("ObjectTrack"))


def test_enumerations_are_the_dbcs_val_tables():
    assert dict(MODE_NAMES) == _val("SafetyOverride", "Mode") == {m.value: m.name for m in Mode}
    assert {name.upper(): code for name, code in STRATEGY_CODES.items()} == \
        {v: k for k, v in _val("EcuStatus", "Strategy").items()}
    assert STRATEGIES == tuple(STRATEGY_CODES)
    with pytest.raises(KeyError):
        enumeration("WheelSpeeds", "WheelSpeedFL")


def test_limits_and_units():
    assert BRAKE_DECEL_MAX_MPS2 == DB.get_message_by_name("SafetyOverride").get_signal_by_name(
        "BrakeDecelRequest").maximum
    assert CoreParams().contingency_decel_mps2 == BRAKE_DECEL_MAX_MPS2
    assert signal_dbc_per_si("WheelSpeeds", "WheelSpeedFL") == KMH_PER_MPS == 3.6
    assert signal_dbc_per_si("DriverInput", "AccelPedal") == 100.0
    with pytest.raises(KeyError):
        dbc_per_si("furlongs/fortnight")


@pytest.mark.parametrize("key, value", [("cycle_s", 0.02), ("status_period_cycles", 5),
                                        ("object_timeout_s", 0.04), ("contingency_decel_mps2", 16.0)])
def test_config_contradicting_the_contract_is_refused(key, value):
    with pytest.raises(EcuConfigError, match=key):
        EcuConfig.from_dict({key: value})


def test_one_configuration_error_class():
    import can_dbc.errors
    import cosim.errors
    import ecu.errors

    assert ecu.errors.ConfigError is cosim.errors.ConfigError is can_dbc.errors.ConfigError
    assert issubclass(can_dbc.errors.ConfigError, ValueError)


def test_fault_bits_are_the_dbcs_fault_signals():
    """Fault bit k is EcuStatus's k-th one-bit Fault* signal, at bit 50 + k (read by cantools on its own)."""
    from can_dbc.contract import FAULT_BIT0, FAULT_SIGNALS
    from ecu.bus_port import FAULT_SIGNALS as BUS_FAULT_SIGNALS, fault_flags_of, fault_signals
    from ecu.core import FaultFlag

    faults = [s for s in DB.get_message_by_name("EcuStatus").signals if s.name.startswith("Fault")]
    assert FAULT_BIT0 == 50 and len(faults) == len(FaultFlag) == 13
    for sig in faults:
        bit = sig.start - FAULT_BIT0
        assert sig.length == 1 and FAULT_SIGNALS[bit] == sig.name == BUS_FAULT_SIGNALS[FaultFlag(bit)]
        assert FaultFlag(bit).name.replace("_", "") == sig.name.removeprefix("Fault").upper()
    assert FaultFlag.E2E == 3 and FaultFlag.SEQUENCE == 12
    every = (1 << len(FaultFlag)) - 1
    assert fault_flags_of(fault_signals(every)) == every and fault_signals(1 << FaultFlag.AUTH)["FaultAuth"] == 1
