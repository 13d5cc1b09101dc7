"""scripts/eval_localisation's library: the square, the depth rendering, arguments, a tiny run."""
import numpy as np
import pytest
from sim2d.camera import CameraConfig

from tamp_bringup.tools import eval_localisation as evaluation


def test_square_path_walks_the_outline_at_the_step():
    points = evaluation.square_path(0.3)
    assert len(points) == 16                           # 4 sides of 1.2 m at 0.3 m
    steps = np.hypot(*np.diff(points, axis=0).T)
    assert np.allclose(steps, 0.3)
    assert all(evaluation.distance_to_square(p) == pytest.approx(0.0) for p in points)


@pytest.mark.parametrize("point, distance", [
    ((1.0, 0.0), 0.5),       # in front of the front edge
    ((2.1, 0.0), 0.6),       # the centre: 0.6 m to every edge
    ((3.0, 1.0), 0.5),       # beyond the far corner (2.7, 0.6): hypot(0.3, 0.4)
])
def test_distance_to_square(point, distance):
    assert evaluation.distance_to_square(np.array(point)) == pytest.approx(distance)


def test_render_puts_the_person_nearer_than_the_wall_inside_the_box():
    cam = CameraConfig(tilt=0.1)
    depth, (x, y, w, h) = evaluation.render(np.array([2.0, 0.0]), cam, 5.0, 0.0,
                                            np.random.default_rng(0))
    assert depth.shape == (cam.height, cam.width) and w > 0 and h > 0
    inside = depth[y:y + h + 1, x:x + w + 1]
    # the cylinder's front is 1.8 m away along the optical axis, the wall 5 m (noise 2 cm + 1 %)
    assert np.median(inside) == pytest.approx(1.8 / np.cos(0.1), abs=0.15)
    assert np.median(depth[:, : max(1, x - 5)]) == pytest.approx(5.0, abs=0.2)


@pytest.mark.parametrize("argv, message", [
    (["--step", "0"], "--step must be in (0, 1.2] m"),
    (["--background", "2"], "--background must be behind the square"),
    (["--dropout", "1"], "--dropout must be in [0, 1)"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        evaluation.parse_args(argv)
    assert message in capsys.readouterr().err


def test_a_tiny_run_localises_every_frame_and_writes_the_plot(tmp_path, capsys):
    out = tmp_path / "loc.png"
    assert evaluation.main(["--step", "0.6", "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "frames 8, localised 8"
    mean_to_outline = float(lines[2].split("mean ")[1].split(" m")[0])
    assert 0.0 < mean_to_outline < 0.28                # within the seed's mean error
    assert out.read_bytes()[:4] == b"\x89PNG"
