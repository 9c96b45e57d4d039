"""A written run's world as ROS 2 messages: odometry, transforms and a marker scene.

Frames (REP 105 names): ``map`` is the path frame (``x`` along the path, ``y`` to the left,
``z`` up); ``base_link`` the ego at the plant's position output; ``object_<i>`` the centre
of the scenario's i-th object (``[[objects]]`` order). The world is 1-D today: the time
series has ``position_m`` along the path and no ``y_m``/``yaw_rad`` columns, read as 0
until a planar world writes them.

Per time-series row: the ego's ``nav_msgs/msg/Odometry`` and one ``tf2_msgs/msg/TFMessage``
with ``map`` -> ``base_link`` and ``map`` -> each ``object_<i>``. The objects' motion is not
in the time series: it is worked out again with the run's own scene model
(:class:`cosim.world.scene.Scene`, from the resolved configuration) at each row's time and
bumper position, as the master did once per ECU cycle; a gap trigger fires at the same
cycle unless that cycle's gap was within the time series' rounding (6 significant digits)
of the trigger.

The scene, a ``visualization_msgs/msg/MarkerArray`` of frame-locked markers (drawn where
their frame is at each instant, so they move with the transforms at 100 Hz), is written at
the first row and whenever what it draws changes (:func:`scene_changes`): the ECU's mode
or its stopping distance (10 Hz). Each holds the whole scene, so a viewer that seeks
shows it from the last message alone:

* the ego as a box ``[bumper - length_m, bumper]`` by ``width_m`` (``[plant]``; bumper =
  position + ``front_bumper_offset_m``), coloured by the ECU's mode;
* each object as a box of its ``length_m`` by ``width_m``, with its name above it;
* the ECU's stopping path: a line from the front bumper, straight ahead, as long as the
  ``StoppingDistance`` of the last ``EcuStatus`` frame at or before the row, in the mode's
  colour; absent before the first status frame.

Box heights are for display only (the world is flat): :data:`DISPLAY_HEIGHT_M`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..world.ego import EgoBody
from ..world.plant_fmu import PlantPose
from ..world.scene import Scene
from ..world.scene_build import build_objects, build_road
from .mcap_schemas import Schemas

MAP_FRAME = "map"
EGO_FRAME = "base_link"
#: box heights (m), display only
DISPLAY_HEIGHT_M = {"ego": 1.5, "object": 1.7}
PATH_WIDTH_M = 0.3  # the stopping path's line width
#: mode -> RGB of the ego's box and its stopping path (others: grey)
MODE_COLORS = {"STANDBY": (0.20, 0.65, 0.30), "TIGHTENING": (0.95, 0.70, 0.10),
               "CONTINGENCY": (0.90, 0.15, 0.15), "FAULT": (0.50, 0.50, 0.50)}
OBJECT_COLOR = (0.95, 0.45, 0.05)
_GREY = (0.5, 0.5, 0.5)
_ODOMETRY, _TF, _MARKERS = "nav_msgs/msg/Odometry", "tf2_msgs/msg/TFMessage", "visualization_msgs/msg/MarkerArray"


@dataclass(frozen=True)
class EgoState:
    """One row of the time series as the scene needs it (SI units; ``t_ns``: the log time)."""

    t_ns: int
    t_s: float
    x_m: float
    y_m: float
    yaw_rad: float
    speed_mps: float
    mode: str
    stopping_distance_m: float | None  # the last EcuStatus's, None before the first


@dataclass(frozen=True)
class Shape:
    """One marker: namespace, ``Marker`` type, pose, scale (m), colour (RGBA 0..1), id, points, text."""

    ns: str
    kind: int
    pose: Any
    scale: tuple[float, float, float]
    rgba: tuple[float, float, float, float]
    id: int = 0
    points: tuple = ()
    text: str = ""


class SceneMessages:
    """Builds the odometry, transform and marker messages of each row (module docstring)."""

    def __init__(self, schemas: Schemas, scenario: Any) -> None:
        self._s = schemas
        self._types = {name: schemas.type(f"{pkg}/msg/{name}") for pkg, name in (
            ("builtin_interfaces", "Duration"), ("std_msgs", "ColorRGBA"), ("geometry_msgs", "Point"), ("geometry_msgs", "Quaternion"),
            ("geometry_msgs", "Pose"), ("geometry_msgs", "Vector3"), ("geometry_msgs", "Twist"),
            ("geometry_msgs", "PoseWithCovariance"), ("geometry_msgs", "TwistWithCovariance"),
            ("geometry_msgs", "Transform"), ("geometry_msgs", "TransformStamped"),
            ("sensor_msgs", "CompressedImage"), ("visualization_msgs", "MeshFile"),
            ("visualization_msgs", "Marker"))}
        plant = scenario.plant
        self._ego_len_m, self._ego_width_m = plant.length_m, plant.width_m
        self._bumper_offset_m = plant.front_bumper_offset_m
        self._objects = scenario.scene_objects()
        self._body = EgoBody(plant)  # the run's own scene model, replayed along the logged ego pose
        self._scene = Scene(build_objects(scenario, build_road(scenario.road)), self._body, scenario.radar,
                            scenario.end)
        self._level = self._quaternion(0.0)
        self._covariance = np.zeros(36, dtype=np.float64)
        self._empty_bytes = np.zeros(0, dtype=np.uint8)

    # -- small builders ---------------------------------------------------------------------
    def _quaternion(self, yaw_rad: float) -> Any:
        return self._types["Quaternion"](0.0, 0.0, math.sin(yaw_rad / 2.0), math.cos(yaw_rad / 2.0))

    def _point(self, x: float, y: float, z: float = 0.0) -> Any:
        return self._types["Point"](float(x), float(y), float(z))

    def _marker(self, header: Any, shape: Shape) -> Any:
        t = self._types
        return t["Marker"](header, shape.ns, shape.id, shape.kind, t["Marker"].ADD, shape.pose,
                           t["Vector3"](*map(float, shape.scale)), t["ColorRGBA"](*map(float, shape.rgba)),
                           t["Duration"](0, 0), True, list(shape.points), [], "",
                           t["CompressedImage"](header, "", self._empty_bytes), [], shape.text, "",
                           t["MeshFile"]("", self._empty_bytes), False)

    # -- the messages ------------------------------------------------------------------------
    def odometry(self, ego: EgoState) -> bytes:
        """``nav_msgs/msg/Odometry``: the ego's pose in ``map`` and its speed along its heading."""
        t = self._types
        pose = t["Pose"](self._point(ego.x_m, ego.y_m), self._quaternion(ego.yaw_rad))
        twist = t["Twist"](t["Vector3"](float(ego.speed_mps), 0.0, 0.0), t["Vector3"](0.0, 0.0, 0.0))
        message = self._s.type(_ODOMETRY)(self._s.header(ego.t_ns, MAP_FRAME), EGO_FRAME,
                                          t["PoseWithCovariance"](pose, self._covariance),
                                          t["TwistWithCovariance"](twist, self._covariance))
        return self._s.serialize(message, _ODOMETRY)

    def transform(self, ego: EgoState) -> bytes:
        """``tf2_msgs/msg/TFMessage``: ``map`` -> ``base_link`` and ``map`` -> each ``object_<i>`` at the row."""
        t = self._types
        header = self._s.header(ego.t_ns, MAP_FRAME)
        moved = t["Transform"](t["Vector3"](float(ego.x_m), float(ego.y_m), 0.0), self._quaternion(ego.yaw_rad))
        frames = [t["TransformStamped"](header, EGO_FRAME, moved)]
        if self._scene:
            pose = PlantPose(ego.x_m, ego.speed_mps, ego.y_m, ego.yaw_rad, 0.0, ego.speed_mps, 0.0)
            self._scene.observe(ego.t_s, self._body.at(pose))
            for i, (obj, st) in enumerate(zip(self._scene.objects, self._scene.states(ego.t_s))):
                x_m, y_m = obj.centre(st)
                centre = t["Vector3"](float(x_m), float(y_m), 0.0)
                place = t["Transform"](centre, self._quaternion(st.yaw_rad))
                frames.append(t["TransformStamped"](header, object_frame(i), place))
        return self._s.serialize(self._s.type(_TF)(frames), _TF)

    def markers(self, ego: EgoState) -> bytes:
        """``visualization_msgs/msg/MarkerArray``: the ego, the objects and the stopping path, frame-locked."""
        mode_rgb = MODE_COLORS.get(ego.mode, _GREY)
        height, kinds = DISPLAY_HEIGHT_M["ego"], self._types["Marker"]
        ego_header = self._s.header(ego.t_ns, EGO_FRAME)
        box_x = self._bumper_offset_m - self._ego_len_m / 2.0
        markers = [self._marker(ego_header, Shape("ego", kinds.CUBE, self._pose(box_x, 0.0, height / 2.0),
                                                  (self._ego_len_m, self._ego_width_m, height), (*mode_rgb, 0.9)))]
        height = DISPLAY_HEIGHT_M["object"]
        for i, obj in enumerate(self._objects):
            header = self._s.header(ego.t_ns, object_frame(i))
            markers.append(self._marker(header, Shape("objects", kinds.CUBE, self._pose(0.0, 0.0, height / 2.0),
                                                      (obj.length_m, obj.width_m, height), (*OBJECT_COLOR, 0.9), i)))
            markers.append(self._marker(header, Shape("object_names", kinds.TEXT_VIEW_FACING,
                                                      self._pose(0.0, 0.0, height + 0.6), (0.0, 0.0, 0.6),
                                                      (0.1, 0.1, 0.1, 1.0), i, text=obj.name)))
        if ego.stopping_distance_m is not None:
            ends = (self._point(self._bumper_offset_m, 0.0, 0.05),
                    self._point(self._bumper_offset_m + ego.stopping_distance_m, 0.0, 0.05))
            path = Shape("stopping_path", kinds.LINE_STRIP, self._pose(0.0, 0.0, 0.0), (PATH_WIDTH_M, 0.0, 0.0),
                         (*mode_rgb, 1.0), points=ends)
            markers.append(self._marker(ego_header, path))
        return self._s.serialize(self._s.type(_MARKERS)(markers), _MARKERS)

    def _pose(self, x: float, y: float, z: float) -> Any:
        return self._types["Pose"](self._point(x, y, z), self._level)


def object_frame(index: int) -> str:
    """The TF frame of the scenario's ``index``-th object."""
    return f"object_{index}"


def scene_changes(egos: Sequence[EgoState]) -> list[EgoState]:
    """The rows at which the scene is written: the first, and each whose mode or stopping distance differs
    from the row before."""
    return [e for i, e in enumerate(egos) if i == 0 or (e.mode, e.stopping_distance_m)
            != (egos[i - 1].mode, egos[i - 1].stopping_distance_m)]


def stopping_distances(times_ns: Sequence[int], status: Sequence[tuple[int, float]]) -> list[float | None]:
    """For each time, the last status value at or before it (None before the first); both sorted."""
    out, k, value = [], 0, None
    for t in times_ns:
        while k < len(status) and status[k][0] <= t:
            value = status[k][1]
            k += 1
        out.append(value)
    return out
