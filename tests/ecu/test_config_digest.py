"""Issue 25, item 4: the digest of an ECU's settings, and the EcuIdentity frame that announces it.

``config_digest`` is computed on both sides of the bus from an ``EcuConfig``: it must change with
every setting, not with how the configuration was written, and not with the two fields that
do not decide what the ECU does (``sim_time``, ``key_file``).
"""

from __future__ import annotations

import dataclasses
import importlib.metadata
import uuid

import can
import pytest

from can_dbc import (AUTHENTICATORS, LAYOUTS, CounterSequence, Receiver, SecOcSender, SecOcVerifier, encode,
                     generate_key)
from ecu import EcuConfig, EcuNode
from ecu.config_digest import (NOT_DIGESTED, SOFTWARE_VERSION, announced_digest, config_digest, digest_of,
                               identity_signals, settings_of)

IDENTITY_ID = LAYOUTS["EcuIdentity"].frame_id


def _other(value):
    """A value of the same type that differs from ``value``."""
    if isinstance(value, bool):
        return not value
    if isinstance(value, int):
        return value + 1
    if isinstance(value, float):
        return value * 1.5 + 0.25
    return value + "x"


def test_the_digest_covers_every_setting_but_the_pacing_and_the_key_files_place():
    config = EcuConfig()
    declared = {f.name for f in dataclasses.fields(config) if f.init}
    assert NOT_DIGESTED == {"sim_time", "key_file"}
    assert set(settings_of(config)) == declared - NOT_DIGESTED


@pytest.mark.parametrize("name", sorted(settings_of(EcuConfig())))
def test_any_change_of_a_setting_changes_the_digest(name):
    settings = settings_of(EcuConfig())
    changed = dict(settings, **{name: _other(settings[name])})
    assert digest_of(changed) != digest_of(settings)


@pytest.mark.parametrize("changes", [{"peak_decel_mps2": 6.5}, {"strategy": "conservative"}, {"standoff_m": 2.1},
                                     {"abs_slip_cycles": 4}, {"driven_axle": "rear"}])
def test_a_changed_config_has_another_digest_and_another_announced_one(changes):
    assert config_digest(EcuConfig(**changes)) != config_digest(EcuConfig())
    assert announced_digest(EcuConfig(**changes)) != announced_digest(EcuConfig())


def test_the_digest_does_not_depend_on_how_the_config_was_written(tmp_path):
    settings = settings_of(EcuConfig())
    assert digest_of(dict(reversed(list(settings.items())))) == digest_of(settings)  # name order, not key order
    assert config_digest(EcuConfig(peak_decel_mps2=7)) == config_digest(EcuConfig(peak_decel_mps2=7.0))
    toml = tmp_path / "scenario.toml"  # a scenario file's [ecu], its other tables left to the scenario
    toml.write_text('[scenario]\nduration_s = 3.0\n[ecu]\nstrategy = "tightening"\npeak_decel_mps2 = 6\n')
    assert config_digest(EcuConfig.from_toml(toml)) == config_digest(EcuConfig(peak_decel_mps2=6.0))
    assert config_digest(EcuConfig(sim_time=True, key_file="/x/secoc.key")) == config_digest(EcuConfig())


def test_the_software_version_is_the_packages():
    assert ".".join(map(str, SOFTWARE_VERSION)) == importlib.metadata.version("crd")


def _clocked_run(node: EcuNode, bus: can.BusABC, cycles: int, key: bytes | None = None) -> list[can.Message]:
    """Run ``cycles`` sim-time cycles from t = 0 (a clock only, authenticated with ``key``); the node's frames."""
    clock, out = CounterSequence(), []
    signer = SecOcSender(key) if key is not None else None
    for k in range(cycles):
        tick = encode("SimClock", {"SimTimeMs": 10 * k}, clock.next())
        for msg in [tick] + ([signer.authenticator(tick)] if signer else []):
            node.on_sim_message(msg)
        while (msg := bus.recv(0.0)) is not None:
            out.append(msg)
    return out


@pytest.mark.parametrize("keyed", [False, True], ids=["E2E", "SecOC"])
def test_a_standalone_ecu_announces_itself_in_its_first_cycle_and_each_second(keyed):
    channel = f"id-{uuid.uuid4().hex[:8]}"
    key = generate_key() if keyed else None
    with can.Bus(interface="virtual", channel=channel) as ecu_bus, can.Bus(interface="virtual", channel=channel) as bus:
        config = EcuConfig(sim_time=True, peak_decel_mps2=6.5)
        node = EcuNode(ecu_bus, config, key=key, standalone=True)
        frames = _clocked_run(node, bus, 250, key)
    rx = Receiver(names=["EcuIdentity"], secoc=SecOcVerifier(key) if keyed else None)
    announced = [f for f in (rx.check(m) for m in frames if m.arbitration_id in (IDENTITY_ID, AUTHENTICATORS[
        "EcuIdentity"])) if f is not None]
    assert len(announced) == 3  # cycles 0, 100 and 200
    assert all(f.signals["ConfigDigest"] == announced_digest(config) for f in announced)
    assert all(f.signals["RunActive"] == 1 and f.signals["ConfigStrategy"] == config.strategy_code for f in announced)
    assert identity_signals(config)["SoftwareVersionMinor"] == announced[0].signals["SoftwareVersionMinor"]


def test_an_ecu_the_cosimulation_steps_announces_nothing_and_a_standalone_one_starts_at_zero():
    channel = f"id-{uuid.uuid4().hex[:8]}"
    with can.Bus(interface="virtual", channel=channel) as ecu_bus, can.Bus(interface="virtual", channel=channel) as bus:
        inner = EcuNode(ecu_bus, EcuConfig(sim_time=True))
        assert not [m for m in _clocked_run(inner, bus, 150) if m.arbitration_id == IDENTITY_ID]
        standalone = EcuNode(ecu_bus, EcuConfig(sim_time=True), standalone=True)
        late = standalone.on_sim_message(encode("SimClock", {"SimTimeMs": 1230}, 0))
        assert late is None and standalone.stats["clock_errors"] == 1 and standalone.cycles == 0
