"""What a vehicle equips the ECU with: which frames it receives and which requests it sends.

The frame set follows the equipment (issue 20's speed figures: every frame costs encode, E2E,
SecOC, decode and logging, and the planar frames nobody used were half of a 1-D run's traffic):

* ``longitudinal``: wheel speeds, the driver's pedals and wheel, the 1-D radar's
  ``ObjectTrack`` in; ``SafetyOverride`` out (every 1-D scene);
* ``planar``: also the ESC's ``EscDynamics`` and the 2-D radar's ``RadarTrack0..7`` in (a
  scene of the plane, :attr:`cosim.scenarios.config.Scenario.planar`);
* ``planar_steering``: also ``SteeringOverride`` out: the ECU has steering authority (a planar
  scene whose plant takes the ``[plant.inputs] steer_request`` role, as the builtin plant does);
* ``planar_corner`` and ``planar_steering_corner``: either, and the rear corner radars'
  ``CornerTrack0..3`` in (a planar scene whose ``[radar] corner`` is true: cars beside and behind).

``EcuStatus`` (and, standalone, ``EcuIdentity``) is sent with every equipment. The message
names are the DBC's; their IDs and cycles come from it. The co-simulation derives the
equipment from the scene (``Scenario.equipment``) and sends exactly ``inputs``; a standalone
ECU reads it from its configuration (``EcuConfig.equipment``), so both sides agree on which
frames exist: an ECU neither expects a frame nobody sends nor sends one nobody receives.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import MappingProxyType
from typing import Mapping

from can_dbc.planar import CORNER_SLOTS, TRACK_SLOTS

#: the inputs of the longitudinal core (the SimClock that paces sim-time mode is not an input)
CORE_INPUT_MESSAGES = ("WheelSpeeds", "DriverInput", "ObjectTrack")
#: the planar sensors' frames: the ESC's and the 2-D radar's track slots
PLANAR_INPUT_MESSAGES = ("EscDynamics", *TRACK_SLOTS)
#: the rear corner radars' track slots (fitted on a planar vehicle only)
CORNER_INPUT_MESSAGES = tuple(CORNER_SLOTS)


@dataclass(frozen=True, slots=True)
class Equipment:
    """One equipment: the messages the ECU receives (``inputs``) and the requests it sends each cycle."""

    name: str
    planar: bool  #: the ESC and the 2-D radar are fitted
    steering: bool  #: the ECU has steering authority (sends SteeringOverride)
    doc: str
    corner: bool = False  #: the rear corner radars are fitted (needs the planar sensors)

    @property
    def inputs(self) -> tuple[str, ...]:
        return CORE_INPUT_MESSAGES + (PLANAR_INPUT_MESSAGES if self.planar else ()) + \
            (CORNER_INPUT_MESSAGES if self.corner else ())

    @property
    def requests(self) -> tuple[str, ...]:
        return ("SafetyOverride", "SteeringOverride") if self.steering else ("SafetyOverride",)


#: name -> equipment (the choices of ``EcuConfig.equipment``)
EQUIPMENT: Mapping[str, Equipment] = MappingProxyType({e.name: e for e in (
    Equipment("longitudinal", False, False, "wheel speeds, pedals and the 1-D radar in; SafetyOverride out"),
    Equipment("planar", True, False, "also EscDynamics and RadarTrack0..7 in (the ESC and the 2-D radar)"),
    Equipment("planar_steering", True, True, "planar, and SteeringOverride out (steering authority)"),
    Equipment("planar_corner", True, False, "planar, and CornerTrack0..3 in (the rear corner radars)", True),
    Equipment("planar_steering_corner", True, True, "planar_steering, and CornerTrack0..3 in", True),
)})
DEFAULT = "longitudinal"


def equipment_for(planar: bool, steering: bool, corner: bool = False) -> Equipment:
    """The equipment with these sensors and this authority; steering authority and the corner radars need the
    planar sensors."""
    return next(e for e in EQUIPMENT.values() if e.planar == planar and e.steering == (steering and planar)
                and e.corner == (corner and planar))
