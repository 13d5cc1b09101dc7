"""scripts/make_maps and scripts/plot_map: rendering blueprints, plotting maps, named errors."""
import shutil

import pytest
from tamp_resources import resource

from floorplan.tools.make_maps import main as make_maps_main
from floorplan.tools.plot_map import main as plot_map_main
from floorplan.occupancy_map import load_map


def test_make_maps_renders_the_household_as_committed(tmp_path, capsys):
    blueprint = resource("maps", "blueprints", "household.yaml")
    assert make_maps_main([str(blueprint), "--out-dir", str(tmp_path)]) == 0
    assert capsys.readouterr().out == \
        f"household.yaml -> {tmp_path}/household.yaml (136x236 cells)\n"
    made, committed = load_map(tmp_path / "household.yaml"), load_map(resource("maps",
                                                                               "household.yaml"))
    assert (made.cells == committed.cells).all() and made.resolution == committed.resolution


def test_plot_map_draws_each_map_and_skips_graph_files(tmp_path, capsys):
    for name in ("office_ring.yaml", "office_ring.pgm", "office_ring.graph.yaml"):
        shutil.copy(resource("maps", name), tmp_path / name)
    shutil.copy(resource("maps", "household.yaml"), tmp_path / "bare.yaml")
    shutil.copy(resource("maps", "household.pgm"), tmp_path / "household.pgm")
    out = tmp_path / "png"
    maps = [tmp_path / "office_ring.yaml", tmp_path / "office_ring.graph.yaml",
            tmp_path / "bare.yaml"]
    assert plot_map_main([*map(str, maps), "--out-dir", str(out)]) == 0
    assert capsys.readouterr().out.splitlines() == [
        f"{tmp_path}/office_ring.yaml -> {out}/office_ring.png",
        f"{tmp_path}/bare.yaml -> {out}/bare.png (no graph)"]
    assert sorted(p.name for p in out.iterdir()) == ["bare.png", "office_ring.png"]


@pytest.mark.parametrize("command, what", [(make_maps_main, "blueprint"), (plot_map_main, "map")])
def test_missing_inputs_are_named(command, what, tmp_path, capsys):
    with pytest.raises(SystemExit):
        command([str(tmp_path / "nope.yaml")])
    assert f"no such {what}: {tmp_path / 'nope.yaml'}" in capsys.readouterr().err
