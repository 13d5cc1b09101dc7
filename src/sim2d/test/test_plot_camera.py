"""scripts/plot_camera's library: running the world up to a time, placing the robot, errors."""
import re

import pytest
from tamp_resources import resource

from sim2d.tools import plot_camera as plot_camera
from sim2d.world import World

HOUSEHOLD = resource("config", "worlds", "household.yaml")


def test_camera_view_runs_the_world_and_places_the_robot(lazy_tables):
    world = World.from_file(HOUSEHOLD)
    frame, robot = plot_camera.camera_view(world, "pepper", (1.0, 2.0, 0.5), time_s=0.2)
    assert world.time == pytest.approx(0.2)        # four steps of 0.05 s
    assert robot.state.pose == (1.0, 2.0, 0.5)
    assert frame is not None


def test_unknown_robot_names_the_robots_there(lazy_tables):
    with pytest.raises(ValueError, match="no robot named 'r2d2' in the world \\(it has: pepper\\)"):
        plot_camera.camera_view(World.from_file(HOUSEHOLD), "r2d2")


@pytest.mark.parametrize("argv, message", [
    (["--out", "x.png", "--time", "-1"], "--time must not be negative"),
    (["--out", "x.png", "--world", "/nonexistent.yaml"], "--world: no such world file"),
    ([], "the following arguments are required: --out"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        plot_camera.parse_args(argv)
    assert message in capsys.readouterr().err


def test_main_prints_the_detections_and_writes_the_png(tmp_path, capsys, lazy_tables):
    out = tmp_path / "camera.png"
    assert plot_camera.main(["--out", str(out), "--time", "1"]) == 0
    # Pepper's start pose has the dining table and its cup in view; the household's calibrated
    # camera may miss either (the cup is small at that distance) or box something that is not
    # there (no name)
    line = capsys.readouterr().out
    match = re.fullmatch(r"(\d+) boxes, 0 skeletons: ?(.*)\n", line)
    assert match, line
    names = [item.split(":")[0] for item in match.group(2).split(", ") if item]
    assert len(names) == int(match.group(1))
    assert set(names) <= {"dining_table", "cup_dining", ""}, line
    assert out.read_bytes()[:4] == b"\x89PNG"
