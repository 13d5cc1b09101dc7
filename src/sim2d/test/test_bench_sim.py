"""scripts/bench_sim's library: the reactive controller, step figures, arguments, a tiny run."""
import json

import numpy as np
import pytest

from sim2d.tools import bench_sim as bench

ANGLES = np.linspace(-2.0, 2.0, 181)


def test_steer_turns_on_the_spot_when_blocked_ahead():
    ranges = np.full(ANGLES.size, 5.0)
    ranges[np.abs(ANGLES) < 0.3] = 0.4
    assert bench.steer(ranges, ANGLES) == (0.0, bench.TURN_IN_PLACE)


def test_steer_heads_for_the_open_side():
    ranges = np.where(ANGLES > 1.0, 20.0, 2.0)      # open only far to the left
    v, w = bench.steer(ranges, ANGLES)
    assert v == bench.CRUISE and w == 1.0            # bearing ~1.5 rad * gain, clipped at 1
    v, w = bench.steer(ranges[::-1], ANGLES)         # mirrored: open to the right
    assert v == bench.CRUISE and w == -1.0


def test_step_figures_agree_with_numpy():
    step_us = np.random.default_rng(0).exponential(100.0, 57)
    figures = bench.step_figures(57 * 0.025, 57, step_us.tolist())
    assert figures["step_p50_us"] == pytest.approx(np.percentile(step_us, 50))
    assert figures["step_p99_us"] == pytest.approx(np.percentile(step_us, 99))
    assert figures["us_per_step"] == pytest.approx(step_us.mean())
    assert figures["real_time_factor"] == pytest.approx(57 * 0.025 / (step_us.sum() / 1e6))


@pytest.mark.parametrize("argv, message", [
    (["--seconds", "0"], "--seconds: must be a positive number"),
    (["--accuracy-scans", "0"], "--accuracy-scans must be at least 1"),
    (["--penguin-world", "/nonexistent.yaml"], "--penguin-world: no such world file"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        bench.parse_args(argv)
    assert message in capsys.readouterr().err


def test_a_tiny_run_writes_every_figure(tmp_path, capsys, lazy_tables):
    out = tmp_path / "sim.json"
    assert bench.main(["--seconds", "0.2", "--accuracy-scans", "1", "--json", str(out)]) == 0
    figures = json.loads(out.read_text())
    assert set(figures) == {"penguin", "table_accuracy", "household", "build"}
    penguin, household = figures["penguin"], figures["household"]
    assert penguin["world"] == "config/worlds/office_penguin.yaml"
    assert penguin["steps"] == 8 and penguin["scans"] == 8      # 40 Hz UTM-30LX for 0.2 s
    assert household["steps"] == 8 and household["people"] == 4
    for part in (penguin, household):
        assert 0 < part["step_p50_us"] <= part["step_p99_us"]
    assert figures["table_accuracy"]["beams"] > 1000 and figures["build"] == {}
    printed = capsys.readouterr().out
    assert "real-time factor: penguin" in printed and "step time: penguin p50" in printed


def test_crowds_stand_apart_in_free_space_and_walk_in_sight(lazy_tables):
    from tamp_resources import resource
    from sim2d.tools.bench_crowd import FREE_CLEARANCE, crowd_world
    from sim2d.raycast import segments_clear
    world = crowd_world(resource("config", "worlds") / "office_penguin.yaml", 3, 5, 60.0)
    assert [r.name for r in world.robots] == ["penguin1", "penguin2", "penguin3"]
    assert len(world.people) == 5
    spots = [r.state.pose[:2] for r in world.robots] + [p.pose[:2] for p in world.people]
    for i, (x, y) in enumerate(spots):
        assert world.geometry.clearance(x, y) >= FREE_CLEARANCE
        assert all(np.hypot(x - u, y - v) > 1.5 for u, v in spots[i + 1:])
    for person in world.people:
        turn = person.schedule[0].pose
        assert segments_clear(world.geometry, *person.pose[:2], [turn[:2]])[0]
        assert [e.time for e in person.schedule] == [1.0, 21.0, 41.0]


def test_windowed_and_every_beam_crowds_drive_the_same_run(capsys, lazy_tables):
    """The overlays see the same ranges, cast together or one by one, so the steered robots
    take the same paths; the --crowd table prints one row per robots x people."""
    from tamp_resources import resource
    from sim2d.tools.bench_crowd import CROWD_RUNS, crowd_world, run_crowd
    template = resource("config", "worlds") / "office_penguin.yaml"
    runs = []
    for _, windowed, batch in CROWD_RUNS:
        world = crowd_world(template, 3, 6, 3.0)
        start = np.array([r.state.pose[:2] for r in world.robots])
        factor, scans = run_crowd(world, 3.0, bench.steer, windowed, batch)
        assert factor > 0 and scans == 3 * 120          # UTM-30LX at 40 Hz
        runs.append([r.state.pose for r in world.robots])
        moved = np.hypot(*(np.array(runs[-1])[:, :2] - start).T)
        assert (moved > 0.3).all()                      # driving, so the scans change
    assert runs[0] == runs[1]                           # together: the same scans exactly
    np.testing.assert_allclose(runs[0], runs[2], atol=1e-9)
