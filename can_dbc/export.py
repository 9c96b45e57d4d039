"""Export the contract to the formats other tools read: AUTOSAR 4 ARXML, KCD and SYM.

KCD and SYM come from cantools' own writers. ARXML is written here, because the
converters at hand lose the contract on the way: canmatrix's ARXML 4 export omits
``BASE-TYPE-ENCODING`` (cantools refuses the file) and loses every scaling, and its
ARXML 3 export loses the scalings too.

The ARXML is an AUTOSAR 4 system description (namespace ``http://autosar.org/schema/r4.0``)
in one package named after the DBC's ``DBName``, with one sub-package per kind:

- ``Cluster``: the CAN cluster (``BAUDRATE`` from the DBC's ``Baudrate``), one physical
  channel, one ``CAN-FRAME-TRIGGERING`` per message (11-bit ``IDENTIFIER``);
- ``Frames``, ``PDUs``: a ``CAN-FRAME`` (8 bytes) carrying one ``I-SIGNAL-I-PDU`` at bit 0
  with the message's cycle time (``CYCLIC-TIMING``, s) and its signal mappings
  (``START-POSITION`` = the DBC start bit, Intel byte order = ``MOST-SIGNIFICANT-BYTE-LAST``);
- ``ISignals``, ``SystemSignals``: the signal's length, raw start value (``GenSigStartValue``),
  base type, comment and computation method;
- ``CompuMethods``: ``LINEAR`` (raw limits, ``phys = offset + factor * raw``) or, with an
  enumeration, ``SCALE_LINEAR_AND_TEXTTABLE``; ``Units``, ``BaseTypes`` (``uintN``/``sintN``);
- ``ECUs``: one ``ECU-INSTANCE`` per node with an OUT PDU group (what it sends) and an IN
  group (what it receives), so readers recover senders and receivers.

Element names follow the AUTOSAR 4 XML schema as cantools' ARXML reader reads them.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import cantools

from .database import DATABASE

FORMATS = ("arxml", "kcd", "sym")
AR_NAMESPACE = "http://autosar.org/schema/r4.0"
DEFAULT_BAUDRATE = 500_000


def _el(parent: ET.Element, tag: str, text: object = None, **attrs: str) -> ET.Element:
    child = ET.SubElement(parent, tag, {k.replace("_", "-").upper(): v for k, v in attrs.items()})
    if text is not None:
        child.text = str(text)
    return child


def _ref(parent: ET.Element, tag: str, dest: str, path: str) -> None:
    _el(parent, f"{tag}-REF", path, dest=dest)


def _desc(parent: ET.Element, comment: str | None) -> None:
    if comment:
        _el(_el(parent, "DESC"), "L-2", comment, l="EN")


def _package(parent: ET.Element, name: str) -> tuple[ET.Element, ET.Element]:
    """A sub-package of ``parent`` (an ``AR-PACKAGES``) and its ``ELEMENTS``."""
    pkg = _el(parent, "AR-PACKAGE")
    _el(pkg, "SHORT-NAME", name)
    return pkg, _el(pkg, "ELEMENTS")


def _number(value: float) -> str:
    return str(int(value)) if float(value).is_integer() else repr(float(value))


def _base_type_name(signal) -> str:
    bits = next(b for b in (8, 16, 32, 64) if signal.length <= b)
    return f"{'s' if signal.is_signed else 'u'}int{bits}"


def _raw_limits(signal) -> tuple[int, int]:
    lo = (signal.minimum - signal.offset) / signal.scale
    hi = (signal.maximum - signal.offset) / signal.scale
    return math.ceil(round(lo, 9)), math.floor(round(hi, 9))


def _compu_method(elements: ET.Element, signal, root: str) -> None:
    method = _el(elements, "COMPU-METHOD")
    _el(method, "SHORT-NAME", signal.name)
    _el(method, "CATEGORY", "SCALE_LINEAR_AND_TEXTTABLE" if signal.choices else "LINEAR")
    if signal.unit:
        _ref(method, "UNIT", "UNIT", f"{root}/Units/{_unit_name(signal.unit)}")
    scales = _el(_el(method, "COMPU-INTERNAL-TO-PHYS"), "COMPU-SCALES")
    lo, hi = _raw_limits(signal)
    scale = _el(scales, "COMPU-SCALE")
    _el(scale, "LOWER-LIMIT", lo, interval_type="CLOSED")
    _el(scale, "UPPER-LIMIT", hi, interval_type="CLOSED")
    coeffs = _el(scale, "COMPU-RATIONAL-COEFFS")
    numerator = _el(coeffs, "COMPU-NUMERATOR")
    _el(numerator, "V", _number(signal.offset))
    _el(numerator, "V", _number(signal.scale))
    _el(_el(coeffs, "COMPU-DENOMINATOR"), "V", "1")
    for value, label in sorted((int(k), str(v)) for k, v in (signal.choices or {}).items()):
        entry = _el(scales, "COMPU-SCALE")
        _el(entry, "SHORT-LABEL", label)
        _el(entry, "LOWER-LIMIT", value, interval_type="CLOSED")
        _el(entry, "UPPER-LIMIT", value, interval_type="CLOSED")
        _el(_el(entry, "COMPU-CONST"), "VT", label)


def _unit_name(unit: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in unit) or "NoUnit"


def _conditional_props(parent: ET.Element, props_tag: str) -> ET.Element:
    return _el(_el(_el(parent, props_tag), "SW-DATA-DEF-PROPS-VARIANTS"), "SW-DATA-DEF-PROPS-CONDITIONAL")


def _signal_elements(pkgs: dict[str, ET.Element], signal, root: str) -> None:
    i_signal = _el(pkgs["ISignals"], "I-SIGNAL")
    _el(i_signal, "SHORT-NAME", signal.name)
    initial = signal.raw_initial if signal.raw_initial is not None else 0
    _el(_el(_el(i_signal, "INIT-VALUE"), "NUMERICAL-VALUE-SPECIFICATION"), "VALUE", _number(initial))
    _el(i_signal, "LENGTH", signal.length)
    props = _conditional_props(i_signal, "NETWORK-REPRESENTATION-PROPS")
    _ref(props, "BASE-TYPE", "SW-BASE-TYPE", f"{root}/BaseTypes/{_base_type_name(signal)}")
    _ref(i_signal, "SYSTEM-SIGNAL", "SYSTEM-SIGNAL", f"{root}/SystemSignals/{signal.name}")
    system = _el(pkgs["SystemSignals"], "SYSTEM-SIGNAL")
    _el(system, "SHORT-NAME", signal.name)
    _desc(system, signal.comment)
    props = _conditional_props(system, "PHYSICAL-PROPS")
    _ref(props, "COMPU-METHOD", "COMPU-METHOD", f"{root}/CompuMethods/{signal.name}")
    if signal.unit:
        _ref(props, "UNIT", "UNIT", f"{root}/Units/{_unit_name(signal.unit)}")
    _compu_method(pkgs["CompuMethods"], signal, root)


def _pdu(pkgs: dict[str, ET.Element], message, root: str) -> None:
    pdu = _el(pkgs["PDUs"], "I-SIGNAL-I-PDU")
    _el(pdu, "SHORT-NAME", message.name)
    _el(pdu, "LENGTH", message.length)
    mappings = _el(pdu, "I-SIGNAL-TO-PDU-MAPPINGS")
    for signal in message.signals:
        mapping = _el(mappings, "I-SIGNAL-TO-I-PDU-MAPPING")
        _el(mapping, "SHORT-NAME", signal.name)
        _ref(mapping, "I-SIGNAL", "I-SIGNAL", f"{root}/ISignals/{signal.name}")
        _el(mapping, "PACKING-BYTE-ORDER", "MOST-SIGNIFICANT-BYTE-LAST")
        _el(mapping, "START-POSITION", signal.start)
        _signal_elements(pkgs, signal, root)
    if message.cycle_time:
        timing = _el(_el(pdu, "I-PDU-TIMING-SPECIFICATIONS"), "I-PDU-TIMING")
        cyclic = _el(_el(_el(timing, "TRANSMISSION-MODE-DECLARATION"), "TRANSMISSION-MODE-TRUE-TIMING"),
                     "CYCLIC-TIMING")
        _el(_el(cyclic, "TIME-PERIOD"), "VALUE", _number(message.cycle_time / 1000.0))
    _el(pdu, "UNUSED-BIT-PATTERN", 0)


def _frame(pkgs: dict[str, ET.Element], channel: ET.Element, message, root: str) -> None:
    frame = _el(pkgs["Frames"], "CAN-FRAME")
    _el(frame, "SHORT-NAME", message.name)
    _desc(frame, message.comment)
    _el(frame, "FRAME-LENGTH", message.length)
    mapping = _el(_el(frame, "PDU-TO-FRAME-MAPPINGS"), "PDU-TO-FRAME-MAPPING")
    _el(mapping, "SHORT-NAME", message.name)
    _el(mapping, "PACKING-BYTE-ORDER", "MOST-SIGNIFICANT-BYTE-LAST")
    _ref(mapping, "PDU", "I-SIGNAL-I-PDU", f"{root}/PDUs/{message.name}")
    _el(mapping, "START-POSITION", 0)
    trig = _el(channel, "CAN-FRAME-TRIGGERING")
    _el(trig, "SHORT-NAME", message.name)
    _ref(trig, "FRAME", "CAN-FRAME", f"{root}/Frames/{message.name}")
    _el(trig, "CAN-ADDRESSING-MODE", "EXTENDED" if message.is_extended_frame else "STANDARD")
    _el(trig, "CAN-FRAME-RX-BEHAVIOR", "CAN-20")
    _el(trig, "CAN-FRAME-TX-BEHAVIOR", "CAN-20")
    _el(trig, "IDENTIFIER", message.frame_id)


def _ecus(pkgs: dict[str, ET.Element], database, root: str) -> None:
    for node in database.nodes:
        sends = [m.name for m in database.messages if node.name in m.senders]
        receives = [m.name for m in database.messages
                    if any(node.name in s.receivers for s in m.signals)]
        ecu = _el(pkgs["ECUs"], "ECU-INSTANCE")
        _el(ecu, "SHORT-NAME", node.name)
        _desc(ecu, node.comment)
        groups = _el(ecu, "ASSOCIATED-COM-I-PDU-GROUP-REFS")
        for direction, names in (("OUT", sends), ("IN", receives)):
            group_name = f"{node.name}_{direction}"
            _ref(groups, "ASSOCIATED-COM-I-PDU-GROUP", "I-SIGNAL-I-PDU-GROUP", f"{root}/PduGroups/{group_name}")
            group = _el(pkgs["PduGroups"], "I-SIGNAL-I-PDU-GROUP")
            _el(group, "SHORT-NAME", group_name)
            _el(group, "COMMUNICATION-DIRECTION", direction)
            pdus = _el(group, "I-SIGNAL-I-PDUS")
            for name in names:
                _ref(_el(pdus, "I-SIGNAL-I-PDU-REF-CONDITIONAL"), "I-SIGNAL-I-PDU", "I-SIGNAL-I-PDU",
                     f"{root}/PDUs/{name}")


def _cluster(elements: ET.Element, database, bus_name: str, baudrate: int) -> ET.Element:
    cluster = _el(elements, "CAN-CLUSTER")
    _el(cluster, "SHORT-NAME", bus_name)
    variant = _el(_el(cluster, "CAN-CLUSTER-VARIANTS"), "CAN-CLUSTER-CONDITIONAL")
    _el(variant, "BAUDRATE", baudrate)
    channel = _el(_el(variant, "PHYSICAL-CHANNELS"), "CAN-PHYSICAL-CHANNEL")
    _el(channel, "SHORT-NAME", f"{bus_name}_Channel")
    triggerings = _el(channel, "FRAME-TRIGGERINGS")
    _el(variant, "PROTOCOL-NAME", "CAN")
    _el(variant, "PROTOCOL-VERSION", "2.0")
    return triggerings


def to_arxml(database=DATABASE) -> str:
    """The contract as an AUTOSAR 4 system description (see the module docstring)."""
    attrs = database.dbc.attributes
    name = str(attrs["DBName"].value) if "DBName" in attrs else "crd"
    baudrate = int(attrs["Baudrate"].value) if "Baudrate" in attrs else DEFAULT_BAUDRATE
    root = f"/{name}"
    autosar = ET.Element("AUTOSAR", {"xmlns": AR_NAMESPACE})
    top, _ = _package(_el(autosar, "AR-PACKAGES"), name)
    top.remove(top.find("ELEMENTS"))
    subs = _el(top, "AR-PACKAGES")
    kinds = ("Cluster", "Frames", "PDUs", "ISignals", "SystemSignals", "CompuMethods", "Units",
             "BaseTypes", "ECUs", "PduGroups")
    pkgs = {kind: _package(subs, kind)[1] for kind in kinds}
    channel = _cluster(pkgs["Cluster"], database, name, baudrate)
    for message in database.messages:
        _frame(pkgs, channel, message, root)
        _pdu(pkgs, message, root)
    for unit in sorted({s.unit for m in database.messages for s in m.signals if s.unit}):
        element = _el(pkgs["Units"], "UNIT")
        _el(element, "SHORT-NAME", _unit_name(unit))
        _el(element, "DISPLAY-NAME", unit)
    for base in sorted({_base_type_name(s) for m in database.messages for s in m.signals}):
        element = _el(pkgs["BaseTypes"], "SW-BASE-TYPE")
        _el(element, "SHORT-NAME", base)
        _el(element, "CATEGORY", "FIXED_LENGTH")
        _el(element, "BASE-TYPE-SIZE", base.split("int")[1])
        _el(element, "BASE-TYPE-ENCODING", "2C" if base.startswith("s") else "NONE")
    _ecus(pkgs, database, root)
    ET.indent(autosar)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(autosar, encoding="unicode") + "\n"


def export(fmt: str, out: Path | str, database=DATABASE) -> Path:
    """Write the contract in ``fmt`` (one of :data:`FORMATS`) to ``out``; returns ``out``."""
    if fmt not in FORMATS:
        raise ValueError(f"export format must be one of {FORMATS}, got {fmt!r}")
    writers = {"arxml": to_arxml, "kcd": cantools.database.Database.as_kcd_string,
               "sym": cantools.database.Database.as_sym_string}
    out = Path(out)
    out.write_text(writers[fmt](database), encoding="utf-8")
    return out
