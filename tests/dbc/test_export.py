"""The DBC as other tools read it: cantools reads our ARXML back and decodes a logged run
exactly as from the DBC; canmatrix exports FIBEX and ARXML; KCD and SYM load back;
every message and signal has a comment; the fault bits are named signals; ``crd dbc``
shows enumeration labels and exports.

The logged run is a 3 s closed-loop run in the plane (so with every frame of the contract) that invokes
the contingency (about 2 s of test time).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import can
import cantools
import pytest

from can_dbc import DATABASE, DBC_PATH
from can_dbc.export import export
from ecu.bus_port import FAULT_SIGNALS
from ecu.core.types import FaultFlag

canmatrix_formats = pytest.importorskip("canmatrix.formats", reason="canmatrix is a test dependency")


@pytest.fixture(scope="module")
def logged_run(tmp_path_factory) -> list[can.Message]:
    from cosim.cli.main import main as crd

    tmp = tmp_path_factory.mktemp("run")
    scen = tmp / "s.toml"
    # a steering driver (the wheel held straight) makes it a scene of the plane: its bus carries the planar
    # frames too (a 1-D scene's carries none, ecu.equipment)
    scen.write_text('[scenario]\nduration_s = 3.0\n[object]\nposition_m = 15.0\n'
                    '[driver.steering]\nmodel = "held"\n[ecu]\nstrategy = "conservative"\n')
    assert crd(["run", str(scen), "--out", str(tmp / "o"), "--can-log", "can.blf"]) == 0
    return list(can.LogReader(str(tmp / "o" / "conservative" / "can.blf")))


def test_our_arxml_loads_in_cantools_and_decodes_a_logged_run_identically(logged_run, tmp_path):
    arxml = cantools.database.load_file(str(export("arxml", tmp_path / "c.arxml")))
    assert arxml.buses[0].baudrate == 500_000 and arxml.buses[0].name == "active_safety"
    for message in DATABASE.messages:
        other = arxml.get_message_by_frame_id(message.frame_id)
        assert (other.name, other.cycle_time, other.senders, other.comment) == (
            message.name, message.cycle_time, message.senders, message.comment)
    decoded_ids = set()
    for msg in logged_run:
        for choices in (False, True):
            ours = DATABASE.decode_message(msg.arbitration_id, msg.data, decode_choices=choices)
            theirs = arxml.decode_message(msg.arbitration_id, msg.data, decode_choices=choices)
            assert {k: str(v) for k, v in theirs.items()} == {k: str(v) for k, v in ours.items()}
        decoded_ids.add(msg.arbitration_id)
    assert decoded_ids >= {0x090, 0x0A0, 0x0B0, 0x0C0, 0x3A0, 0x094, 0x0A8, 0x0C2, 0x0D0}  # planar frames too
    modes = {DATABASE.decode_message(0x090, m.data, decode_choices=False)["Mode"] for m in logged_run if m.arbitration_id == 0x090}
    assert len(modes) >= 2  # the run really changes the ECU's mode (enumeration labels covered)


@pytest.mark.parametrize("fmt", ["kcd", "sym"])
def test_kcd_and_sym_exports_load_back(fmt, tmp_path, logged_run):
    other = cantools.database.load_file(str(export(fmt, tmp_path / f"c.{fmt}")))
    msg = next(m for m in logged_run if m.arbitration_id == 0x0C0)
    assert other.decode_message(0x0C0, msg.data) == DATABASE.decode_message(0x0C0, msg.data)


def test_canmatrix_exports_fibex_and_arxml_that_keeps_signals_apart(tmp_path):
    """FIBEX crashed on the missing GenMsgDelayTime definition; canmatrix's ARXML had six
    elements at the path /Cluster/CAN/CAN/CHECKSUM (cantools refused the file for that)."""
    matrices = canmatrix_formats.loadp(str(DBC_PATH))
    canmatrix_formats.dumpp(matrices, str(tmp_path / "c.xml"), export_type="fibex")
    assert (tmp_path / "c.xml").stat().st_size > 0
    canmatrix_formats.dumpp(matrices, str(tmp_path / "c.arxml"))
    paths = arxml_paths(ET.parse(tmp_path / "c.arxml").getroot())
    duplicates = sorted({p for p in paths if paths.count(p) > 1})
    assert not duplicates, duplicates
    assert sum(p.endswith("_CRC") for p in paths) >= len(DATABASE.messages)


def arxml_paths(element: ET.Element, prefix: str = "") -> list[str]:
    """The AUTOSAR path (SHORT-NAMEs from the root) of every named element, as cantools keys them."""
    paths = []
    for child in element:
        name = child.findtext("{*}SHORT-NAME")
        path = f"{prefix}/{name}" if name is not None else prefix
        if name is not None:
            paths.append(path)
        paths.extend(arxml_paths(child, path))
    return paths


def test_attribute_definitions_the_tools_expect():
    defs = DATABASE.dbc.attribute_definitions
    assert {"GenMsgDelayTime", "GenMsgCycleTime", "GenMsgSendType", "GenSigStartValue", "DBName",
            "Baudrate"} <= set(defs)
    assert DATABASE.dbc.attributes["DBName"].value == "active_safety"
    assert DATABASE.buses[0].baudrate == 500_000
    throttle = DATABASE.get_message_by_name("SafetyOverride").get_signal_by_name("ThrottleLimit")
    assert throttle.raw_initial == 1000  # pass-through 100 %


def test_every_message_and_signal_has_a_comment():
    missing = [m.name for m in DATABASE.messages if not m.comment]
    missing += [f"{m.name}.{s.name}" for m in DATABASE.messages for s in m.signals if not s.comment]
    assert not missing, missing


def test_each_fault_bit_is_a_named_one_bit_signal_at_bit_50_plus_k():
    status = DATABASE.get_message_by_name("EcuStatus")
    assert set(FAULT_SIGNALS) == set(FaultFlag)
    for bit, name in FAULT_SIGNALS.items():
        signal = status.get_signal_by_name(name)
        assert (signal.start, signal.length, signal.is_signed) == (50 + bit, 1, False)
        assert {int(k): str(v) for k, v in signal.choices.items()} == {0: "OK", 1: "FAULT"}


def test_crd_dbc_show_prints_enumeration_labels(capsys):
    from cosim.cli.main import main as crd

    assert crd(["dbc", "show"]) == 0
    out = capsys.readouterr().out
    assert "0=STANDBY 1=TIGHTENING 2=CONTINGENCY 3=FAULT" in out
    assert "0=NONE 1=CONSERVATIVE 2=TIGHTENING" in out
