"""Write the FMI 2.0 and FMI 3.0 ``modelDescription.xml`` from the variable table.

Both descriptions come from ``variables.VARIABLES`` so their value references,
start values and units match the C code by construction. Units are declared
with their SI base-unit exponents.
"""

from __future__ import annotations

import json
from xml.sax.saxutils import quoteattr

from fmu_plant.variables import VARIABLES, PlantVariable

MODEL_NAME = "VehiclePlant"
MODEL_IDENTIFIER = "vehicle_plant"
DESCRIPTION = ("Planar vehicle plant: single-track lateral and yaw dynamics, steering actuator, powertrain and brake"
               " lags, Magic Formula tyres in a friction ellipse, ABS")
#: internal fixed step, s (PLANT_STEP_S in src/model.h)
INTERNAL_STEP_S = 1e-3
#: C files compiled into the FMU, per FMI version; they and every header in src/ ship in
#: the FMU's sources/ folder together with the generated plant_token.h
_COMMON_C = ("variables.c", "model.c", "planar.c", "tyre_curve.c", "framework.c", "framework_values.c")
SOURCE_FILES: dict[int, tuple[str, ...]] = {2: (*_COMMON_C, "fmi2_api.c"), 3: (*_COMMON_C, "fmi3_api.c")}
#: headers and included fragments shipped in sources/ (besides plant_token.h)
SOURCE_HEADERS: dict[int, tuple[str, ...]] = {
    2: ("framework.h", "glibc_compat.h", "model.h", "variables.h", "variables.def"),
    3: ("framework.h", "glibc_compat.h", "model.h", "variables.h", "variables.def", "fmi3_unsupported.inc"),
}

#: unit name -> SI base-unit exponents (FMI 2.0.4 section 2.2.2)
UNIT_BASES: dict[str, dict[str, int]] = {
    "1": {},
    "s": {"s": 1},
    "m": {"m": 1},
    "m2": {"m": 2},
    "m/s": {"m": 1, "s": -1},
    "m/s2": {"m": 1, "s": -2},
    "rad": {"rad": 1},
    "rad/s": {"rad": 1, "s": -1},
    "1/rad": {"rad": -1},
    "N": {"kg": 1, "m": 1, "s": -2},
    "W": {"kg": 1, "m": 2, "s": -3},
    "kg": {"kg": 1},
    "kg/m3": {"kg": 1, "m": -3},
    "kg.m2": {"kg": 1, "m": 2},
}

_CAUSALITY = {"INDEPENDENT": "independent", "INPUT": "input", "OUTPUT": "output", "PARAMETER": "parameter"}
_VARIABILITY = {"INDEPENDENT": "continuous", "INPUT": "continuous", "OUTPUT": "continuous", "PARAMETER": "fixed"}


class DescriptionError(ValueError):
    """The variable table uses something the description writer cannot express."""


def _start_text(var: PlantVariable) -> str:
    if var.type == "BOOL":
        return "true" if var.start else "false"
    return repr(float(var.start))


def _has_start(var: PlantVariable) -> bool:
    return var.kind in ("INPUT", "PARAMETER")


def _unit_definitions() -> list[str]:
    used = sorted({v.unit for v in VARIABLES if v.type == "REAL"})
    unknown = [u for u in used if u not in UNIT_BASES]
    if unknown:
        raise DescriptionError(f"units {unknown} have no entry in UNIT_BASES; known: {sorted(UNIT_BASES)}")
    lines = ["  <UnitDefinitions>"]
    for unit in used:
        exps = " ".join(f'{k}="{v}"' for k, v in UNIT_BASES[unit].items())
        lines.append(f"    <Unit name={quoteattr(unit)}><BaseUnit {exps}/></Unit>".replace("<BaseUnit />", "<BaseUnit/>"))
    lines.append("  </UnitDefinitions>")
    return lines


def _common_attrs(var: PlantVariable) -> str:
    attrs = f"name={quoteattr(var.name)} valueReference=\"{var.vr}\" description={quoteattr(var.description)}"
    attrs += f' causality="{_CAUSALITY[var.kind]}"'
    if var.kind != "INDEPENDENT":
        attrs += f' variability="{_VARIABILITY[var.kind]}"'
    return attrs


def _fmi2_variable(var: PlantVariable) -> str:
    start = f" start={quoteattr(_start_text(var))}" if _has_start(var) else ""
    if var.type == "BOOL":
        return f"    <ScalarVariable {_common_attrs(var)}><Boolean{start}/></ScalarVariable>"
    return f"    <ScalarVariable {_common_attrs(var)}><Real unit={quoteattr(var.unit)}{start}/></ScalarVariable>"


def render_fmi2(token: str) -> str:
    """modelDescription.xml for FMI 2.0 co-simulation; ``token`` is the GUID."""
    indices = {var.vr: i for i, var in enumerate(VARIABLES, start=1)}
    outputs = [f'      <Unknown index="{indices[v.vr]}"/>' for v in VARIABLES if v.kind == "OUTPUT"]
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<fmiModelDescription fmiVersion="2.0" modelName="{MODEL_NAME}" guid={quoteattr(token)}'
        f' description="{DESCRIPTION}" generationTool="crd fmu_plant" variableNamingConvention="flat"'
        ' numberOfEventIndicators="0">',
        f'  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" canHandleVariableCommunicationStepSize="true"'
        ' canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true"'
        ' canGetAndSetFMUstate="false" canSerializeFMUstate="false">',
        "    <SourceFiles>", *(f'      <File name="{name}"/>' for name in SOURCE_FILES[2]), "    </SourceFiles>",
        "  </CoSimulation>",
        *_unit_definitions(),
        '  <LogCategories><Category name="logStatusWarning"/><Category name="logStatusError"/>'
        '<Category name="logStatusFatal"/></LogCategories>',
        f'  <DefaultExperiment startTime="0.0" stopTime="10.0" stepSize="{INTERNAL_STEP_S!r}"/>',
        "  <ModelVariables>",
        *(_fmi2_variable(v) for v in VARIABLES),
        "  </ModelVariables>",
        "  <ModelStructure>",
        "    <Outputs>", *outputs, "    </Outputs>",
        "    <InitialUnknowns>", *outputs, "    </InitialUnknowns>",
        "  </ModelStructure>",
        "</fmiModelDescription>",
    ]
    return "\n".join(lines) + "\n"


def _fmi3_variable(var: PlantVariable) -> str:
    start = f" start={quoteattr(_start_text(var))}" if _has_start(var) else ""
    if var.type == "BOOL":
        return f"    <Boolean {_common_attrs(var)}{start}/>"
    return f"    <Float64 {_common_attrs(var)} unit={quoteattr(var.unit)}{start}/>"


def render_fmi3(token: str) -> str:
    """modelDescription.xml for FMI 3.0 co-simulation; ``token`` is the instantiationToken."""
    outputs = [v for v in VARIABLES if v.kind == "OUTPUT"]
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<fmiModelDescription fmiVersion="3.0" modelName="{MODEL_NAME}" instantiationToken={quoteattr(token)}'
        f' description="{DESCRIPTION}" generationTool="crd fmu_plant" variableNamingConvention="flat">',
        f'  <CoSimulation modelIdentifier="{MODEL_IDENTIFIER}" canHandleVariableCommunicationStepSize="true"'
        f' fixedInternalStepSize="{INTERNAL_STEP_S!r}"'
        ' canBeInstantiatedOnlyOncePerProcess="false" canGetAndSetFMUState="false"'
        ' canSerializeFMUState="false" hasEventMode="false" providesIntermediateUpdate="false"/>',
        *_unit_definitions(),
        '  <LogCategories><Category name="logStatusWarning"/><Category name="logStatusError"/>'
        '<Category name="logStatusFatal"/></LogCategories>',
        f'  <DefaultExperiment startTime="0.0" stopTime="10.0" stepSize="{INTERNAL_STEP_S!r}"/>',
        "  <ModelVariables>",
        *(_fmi3_variable(v) for v in VARIABLES),
        "  </ModelVariables>",
        "  <ModelStructure>",
        *(f'    <Output valueReference="{v.vr}"/>' for v in outputs),
        *(f'    <InitialUnknown valueReference="{v.vr}"/>' for v in outputs),
        "  </ModelStructure>",
        "</fmiModelDescription>",
    ]
    return "\n".join(lines) + "\n"


def render_build_description() -> str:
    """sources/buildDescription.xml of the FMI 3.0 FMU (FMI 3.0 section 2.5.1)."""
    lines = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        '<fmiBuildDescription fmiVersion="3.0">',
        f'  <BuildConfiguration modelIdentifier="{MODEL_IDENTIFIER}">',
        '    <SourceFileSet language="C11">',
        *(f'      <SourceFile name="{name}"/>' for name in SOURCE_FILES[3]),
        "    </SourceFileSet>",
        '    <Library name="m" description="the C maths library (libm)"/>',
        "  </BuildConfiguration>",
        "</fmiBuildDescription>",
    ]
    return "\n".join(lines) + "\n"


def render_token_header(token: str) -> str:
    """sources/plant_token.h: the GUID / instantiation token the C code checks."""
    return ("/* Generated by fmu_plant/build.py: the token of this FMU's modelDescription.xml. */\n"
            f"#define PLANT_TOKEN {json.dumps(token)}\n")


def render(fmi_version: int, token: str) -> str:
    """The description for ``fmi_version`` 2 or 3."""
    renderers = {2: render_fmi2, 3: render_fmi3}
    if fmi_version not in renderers:
        raise DescriptionError(f"fmi_version must be 2 or 3, got {fmi_version!r}")
    return renderers[fmi_version](token)
