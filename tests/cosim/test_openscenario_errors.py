"""Outside the OpenSCENARIO/OpenDRIVE subset: one test per element class, each a one-line error with file and line."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("scenariogeneration")
from lxml import etree  # noqa: E402

from cosim.errors import ConfigError  # noqa: E402
from cosim.matrix.catalogue import load_catalogue  # noqa: E402
from cosim.scenarios.loader import scenario_from_dict  # noqa: E402
from cosim.scenarios.openscenario import read_xosc  # noqa: E402
from cosim.scenarios.openscenario.export import export_xosc  # noqa: E402


@pytest.fixture()
def ccrb(tmp_path: Path) -> tuple[Path, Path]:
    cell = next(c for c in load_catalogue("ncap_ccr").cells if c.cell_id == "CCRb-50")
    return export_xosc(scenario_from_dict(cell.scenario_dict()), tmp_path, "ccrb")


def _edit(path: Path, xpath: str, xml: str, replace: bool, tag: str) -> int:
    """Put ``xml`` at ``xpath`` (appended, or replacing it); returns the line of its ``tag`` element in the file."""
    tree = etree.parse(str(path))
    target = tree.xpath(xpath)[0]
    new = etree.fromstring(xml)
    if replace:
        target.getparent().replace(target, new)
    else:
        target.append(new)
    where = tree.getpath(next(new.iter(tag)))
    tree.write(str(path))
    return etree.parse(str(path)).xpath(where)[0].sourceline


XOSC_CASES = {  # element class: (xpath, new element, replace?, the element named in the error)
    "entity": ("//Entities", '<ScenarioObject name="cone"><MiscObject mass="1" miscObjectCategory="obstacle" '
               'name="c"><BoundingBox><Center x="0" y="0" z="0"/><Dimensions width="1" length="1" height="1"/>'
               '</BoundingBox><Properties/></MiscObject></ScenarioObject>', False, "MiscObject"),
    "position": ("//Private[@entityRef='Ego']//Position/WorldPosition", '<RelativeWorldPosition entityRef="x" '
                 'dx="1" dy="0"/>', True, "RelativeWorldPosition"),
    "private action": ("//Event//PrivateAction/LongitudinalAction", '<RoutingAction><AssignRouteAction/>'
                       '</RoutingAction>', True, "AssignRouteAction"),
    "lateral action": ("//Event//PrivateAction/LongitudinalAction", '<LateralAction><LaneOffsetAction continuous='
                       '"false"/></LateralAction>', True, "LaneOffsetAction"),
    "global action": ("//Init/Actions", '<GlobalAction><EnvironmentAction/></GlobalAction>', False, "GlobalAction"),
    "dynamics": ("//Event//SpeedActionDynamics", '<SpeedActionDynamics dynamicsShape="sinusoidal" value="4" '
                 'dynamicsDimension="rate"/>', True, "SpeedActionDynamics"),
    "condition": ("//Event//ByValueCondition", '<ByValueCondition><StoryboardElementStateCondition '
                  'storyboardElementType="act" storyboardElementRef="a" state="endTransition"/></ByValueCondition>',
                  True, "StoryboardElementStateCondition"),
    "condition group": ("//Event/StartTrigger", '<ConditionGroup><Condition name="c" delay="0" conditionEdge="rising">'
                        '<ByValueCondition><SimulationTimeCondition value="1" rule="greaterThan"/></ByValueCondition>'
                        '</Condition></ConditionGroup>', False, "ConditionGroup"),
    "parameter reference": ("/OpenSCENARIO/Storyboard/StopTrigger//SimulationTimeCondition",
                            '<SimulationTimeCondition value="$duration" rule="greaterThan"/>', True,
                            "SimulationTimeCondition"),
}


@pytest.mark.parametrize("case", sorted(XOSC_CASES))
def test_unsupported_openscenario_element(ccrb, case: str) -> None:
    xpath, xml, replace, tag = XOSC_CASES[case]
    xosc_path, _ = ccrb
    line = _edit(xosc_path, xpath, xml, replace, tag)
    with pytest.raises(ConfigError) as err:
        read_xosc(xosc_path)
    message = str(err.value)
    assert "\n" not in message
    assert message.startswith(f"{xosc_path}: not supported yet: <{tag}> at line {line}"), message


XODR_CASES = {
    "poly3": ("//geometry/line", '<poly3 a="0" b="0" c="0.001" d="0"/>', True, "poly3"),
    "paramPoly3": ("//geometry/line", '<paramPoly3 aU="0" bU="1" cU="0" dU="0" aV="0" bV="0" cV="0.01" dV="0"/>',
                   True, "paramPoly3"),
    "kink": ("//planView", '<geometry s="1000" x="0" y="5" hdg="0.3" length="10"><line/></geometry>', False,
             "geometry"),
    "lane width polynomial": ("//lane[@id='-1']/width", '<width sOffset="0" a="3.5" b="0.01" c="0" d="0"/>', True,
                              "width"),
    "junction": ("/OpenDRIVE", '<junction id="7" name="j"/>', False, "junction"),
}


@pytest.mark.parametrize("case", sorted(XODR_CASES))
def test_unsupported_opendrive_element(ccrb, case: str) -> None:
    xpath, xml, replace, tag = XODR_CASES[case]
    xosc_path, xodr_path = ccrb
    line = _edit(xodr_path, xpath, xml, replace, tag)
    with pytest.raises(ConfigError, match=rf"^{xodr_path}: not supported yet: <{tag}> at line {line}\b"):
        read_xosc(xosc_path)


def test_ego_is_chosen_by_name_and_option(ccrb) -> None:
    xosc_path, _ = ccrb
    assert read_xosc(xosc_path).plant.initial_speed_mps == pytest.approx(50 / 3.6)
    with pytest.raises(ConfigError, match="<SpeedAction> at line .*an action of the ego in the story"):
        read_xosc(xosc_path, ego="CCRb-50")  # the target as the equipped car: its braking is the ego's now
    with pytest.raises(ConfigError, match="--ego 'nobody': no such entity"):
        read_xosc(xosc_path, ego="nobody")
    text = xosc_path.read_text().replace('name="Ego"', 'name="Car1"').replace('entityRef="Ego"', 'entityRef="Car1"')
    xosc_path.write_text(text)
    with pytest.raises(ConfigError, match="cannot tell the ego among Car1, CCRb-50"):
        read_xosc(xosc_path)


def test_a_bad_crd_property_names_its_line(ccrb) -> None:
    xosc_path, _ = ccrb
    line = _edit(xosc_path, "//ScenarioObject[@name='Ego']/Vehicle/Properties",
                 '<Property name="crd.radar.latency_ms" value="100"/>', False, "Property")
    with pytest.raises(ConfigError, match=rf"^{xosc_path}:{line}: <Property>: radar.latency_ms: unknown key"):
        read_xosc(xosc_path)
