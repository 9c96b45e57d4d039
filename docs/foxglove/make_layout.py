"""Write ``crd-layout.json``: a Foxglove layout that opens a crd run's MCAP file as the paper's figure.

Built with the Foxglove SDK's layout types (``foxglove.layouts``, package ``foxglove-sdk``),
so the file is in the format Foxglove imports. Run it after changing a panel:

    .venv/bin/python docs/foxglove/make_layout.py

``tests/cosim/test_mcap_layout.py`` checks that the committed file is what this script
writes and that every message path in it names a topic and a field of an exported run.

Panels (left: the paper's view; right: the world):

* speed against position (Johnson 2019, Fig. 2) from ``/ego/odometry``;
* speed, and the ECU's own speed estimate, against time;
* the gap to the object ahead against the ECU's stopping distance (the dance);
* the ECU's limits: throttle limit (%) and requested deceleration (m/s²);
* the ECU's mode and whether it overrides the driver, as state transitions;
* a bird's-eye 3D view following the ego (``/scene/markers``, ``/tf``), and the run's events.
"""

from __future__ import annotations

import json
from pathlib import Path

import foxglove.layouts as fl

LAYOUT_PATH = Path(__file__).with_name("crd-layout.json")


def _plot(title: str, series: list[tuple[str, str]], y_label: str, **config) -> fl.PlotPanel:
    """A plot of ``series`` (message path, label); against time, synced with the other panels, unless
    ``config`` says otherwise."""
    paths = [fl.PlotSeries(value=value, label=label, enabled=True) for value, label in series]
    config = {"is_synced": True, "show_legend": True, "legend_display": "top"} | config
    return fl.PlotPanel(title=title, config=fl.PlotConfig(paths=paths, y_axis_label=y_label, **config))


def paper_panels() -> list[fl.SplitItem]:
    """The left column: the paper's figure, then the ECU over time."""
    figure = _plot("Speed against position (the paper's Fig. 2)",
                   [("/ego/odometry.twist.twist.linear.x", "speed (m/s)")], "speed (m/s)",
                   x_axis_val="custom", x_axis_path=fl.PlotXAxisPath(value="/ego/odometry.pose.pose.position.x",
                                                                     enabled=True),
                   x_axis_label="position along the path (m)", is_synced=False)
    speed = _plot("Speed against time", [("/run/sample.speed_mps", "speed (m/s)"),
                                         ("/can/decoded/EcuStatus.speed_estimate", "ECU's speed estimate (m/s)")],
                  "m/s")
    dance = _plot("Gap and the ECU's stopping distance", [("/run/sample.gap_m", "gap to the object (m)"),
                                                          ("/can/decoded/EcuStatus.stopping_distance",
                                                           "stopping distance (m)")], "m")
    limits = _plot("The ECU's limits", [("/can/decoded/SafetyOverride.throttle_limit", "throttle limit (%)"),
                                        ("/can/decoded/SafetyOverride.brake_decel_request",
                                         "requested deceleration (m/s²)")], "%, m/s²")
    mode = fl.StateTransitionsPanel(title="ECU mode", config=fl.StateTransitionsConfig(
        paths=[fl.StateTransitionsSeries(value="/run/sample.ecu_mode", label="mode", enabled=True),
               fl.StateTransitionsSeries(value="/can/decoded/SafetyOverride.override_active",
                                         label="override active", enabled=True)],
        is_synced=True))
    return [fl.SplitItem(proportion=3, content=figure), fl.SplitItem(proportion=2, content=speed),
            fl.SplitItem(proportion=2, content=dance), fl.SplitItem(proportion=2, content=limits),
            fl.SplitItem(proportion=1, content=mode)]


def world_panels() -> list[fl.SplitItem]:
    """The right column: the bird's-eye view following the ego, and the events."""
    camera = fl.ThreeDeeCameraState(perspective=False, distance=90.0, phi=0.0, theta_offset=0.0,
                                    target_offset=(35.0, 0.0, 0.0))
    topics = {"/scene/markers": fl.BaseRendererRosMarkerTopicSettings(visible=True),
              "/ego/odometry": fl.BaseRendererPoseTopicSettings(visible=True, type="arrow")}
    view = fl.ThreeDeePanel(title="Bird's-eye view (ego box coloured by the ECU's mode; its stopping path ahead)",
                            config=fl.ThreeDeeConfig(camera_state=camera, follow_tf="base_link",
                                                     follow_mode="follow-position", fixed_frame="map",
                                                     topics=topics))
    events = fl.LogPanel(title="Events", config=fl.LogConfig(topic_to_render="/run/events"))
    return [fl.SplitItem(proportion=4, content=view), fl.SplitItem(proportion=1, content=events)]


def layout() -> fl.Layout:
    left = fl.SplitContainer(direction="column", items=paper_panels())
    right = fl.SplitContainer(direction="column", items=world_panels())
    return fl.Layout(content=fl.SplitContainer(direction="row", items=[
        fl.SplitItem(proportion=3, content=left), fl.SplitItem(proportion=2, content=right)]))


def layout_text() -> str:
    """The layout as the committed file holds it: indented JSON, keys in the SDK's order."""
    return json.dumps(json.loads(layout().to_json()), indent=2, ensure_ascii=False) + "\n"


if __name__ == "__main__":
    LAYOUT_PATH.write_text(layout_text())
    print(f"wrote {LAYOUT_PATH}")
