"""scripts/eval_activity_home's library: the household's people from a ring of viewpoints."""
import math

import pytest

from tamp_bringup import home_activity_set
from tamp_bringup.tools import eval_activity_home as evaluation
from tamp_resources import resource

WORLD = str(resource("config", "worlds", "household_day.yaml"))


def test_ring_poses_face_the_centre():
    poses = list(home_activity_set.ring((1.0, 2.0), (1.5,), 4))
    assert [(round(x, 6), round(y, 6)) for x, y, _ in poses] == [
        (2.5, 2.0), (1.0, 3.5), (-0.5, 2.0), (1.0, 0.5)]
    for x, y, yaw in poses:
        assert math.cos(yaw) * (1.0 - x) + math.sin(yaw) * (2.0 - y) == pytest.approx(1.5)


def test_viewings_stand_where_the_robot_fits_and_label_what_the_world_says():
    seen = list(home_activity_set.viewings(WORLD, [60.0], distances=(1.8,), bearings=4,
                                           frames=2))
    assert seen and all(len(v.frames) == 2 for v in seen)
    truth = {"Alice": "work", "Bob": "watch TV", "Carol": "read", "David": "read"}
    for viewing in seen:
        if viewing.person in truth:
            assert viewing.activity == truth[viewing.person]


def test_reading_fused_over_frames_beats_each_frame_alone(tmp_path, capsys):
    """David and Carol read at 60 s; a detector that finds the book in some frames only reads
    'read' in most frames once they are fused (perception.activity_track)."""
    out = tmp_path / "home.md"
    assert evaluation.main(["--world", WORLD, "--times", "60", "--out", str(out)]) == 0
    row = next(line for line in out.read_text().splitlines() if line.startswith("| read |"))
    framewise, fused = (float(v) for v in row.split("|")[3:5])
    assert fused > framewise and fused >= 0.8


@pytest.mark.parametrize("argv, message", [
    (["--times", "a,b"], "--times must be comma-separated seconds"),
    (["--window", "-1"], "must not be negative"),
    (["--world", "/nonexistent.yaml"], "--world /nonexistent.yaml: no such file"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        evaluation.parse_args(argv)
    assert message in capsys.readouterr().err
