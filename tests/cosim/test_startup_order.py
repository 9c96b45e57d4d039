"""ClosedLoop opens the ECU link before the plant: a plant that fails to load must still stop a spawned ECU."""

import pytest


from cosim.cli.paper import PAPER_SCENARIO
from cosim.errors import PlantError
from cosim.link.ecu_link import EcuOptions
from cosim.loop import master
from cosim.scenarios.loader import load_scenario


def test_failing_plant_stops_the_spawned_ecu(tmp_path, monkeypatch):
    opened = []

    def recording_open_link(*args, **kwargs):
        link = real_open_link(*args, **kwargs)
        opened.append(link)
        return link

    real_open_link = master.open_link
    monkeypatch.setattr(master, "open_link", recording_open_link)
    broken = tmp_path / "broken.fmu"
    broken.write_bytes(b"not a zip archive")
    with pytest.raises(PlantError, match="not a readable FMU"):
        master.ClosedLoop(load_scenario(PAPER_SCENARIO), broken, "none", ecu=EcuOptions(mode="process"))
    assert len(opened) == 1, "the link is opened before the plant"
    process = opened[0].process
    assert process is not None and process.returncode is not None, "the spawned ECU was stopped"
    assert not process.alive()
