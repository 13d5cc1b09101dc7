"""scripts/bench_nav's library: arguments, free-cell pairs, the timing summary, tiny runs."""
import numpy as np
import pytest
import yaml
from tamp_resources import resource

from nav_mocks.tools import bench_nav as bench


@pytest.mark.parametrize("argv, message", [
    ([], "required: what"),
    (["astar", "--pairs", "0"], "--pairs: must be a positive integer; got '0'"),
    (["navigate", "--goals", "x"], "--goals: must be a positive integer; got 'x'"),
    (["places", "--seeds", "0,a"], "--seeds: must be comma-separated integers"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        bench.argument_parser().parse_args(argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_seeds_are_parsed():
    assert bench.argument_parser().parse_args(["places", "--seeds", "3,5"]).seeds == [3, 5]


def test_random_pairs_are_free_cells():
    blocked = np.ones((6, 8), dtype=bool)
    blocked[2, 3] = blocked[4, 6] = False
    pairs = bench.random_pairs(blocked, 20, np.random.default_rng(0))
    assert len(pairs) == 20
    assert {cell for pair in pairs for cell in pair} <= {(2, 3), (4, 6)}


def test_summary_reports_percentiles_in_ms():
    seconds = np.random.default_rng(1).exponential(0.01, 40)
    ms = 1e3 * seconds
    line = bench.summary("plain A*", seconds.tolist())
    assert line == (f"plain A*: p50 {np.percentile(ms, 50):.1f} ms, p99 "
                    f"{np.percentile(ms, 99):.1f} ms, mean {ms.mean():.1f} ms, max "
                    f"{ms.max():.1f} ms over 40 pairs")


def test_time_astar_on_a_corridor():
    blocked = np.ones((3, 12), dtype=bool)
    blocked[1, 1:11] = False
    times, found, lengths = bench.time_astar(blocked, [((1, 1), (1, 10)), ((1, 1), (0, 0))], 0.1)
    assert len(times) == 2 and found == 1
    assert lengths == [pytest.approx(0.9), 0.0]     # 9 cells of 0.1 m; a blocked goal: none


def test_tiny_astar_run(capsys):
    assert bench.main(["astar", "--pairs", "3"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("map household.yaml:")
    assert len(lines) == 3 and all("p50" in line and "p99" in line and "over 3 pairs" in line
                                   for line in lines[1:])


def march_household(folder):
    """config/worlds/household.yaml with Pepper's laser ray-marched: its range table (what the
    default world uses) takes a fresh machine seconds to tabulate, and the run does not check it."""
    household = resource("config", "worlds", "household.yaml")
    robots = yaml.safe_load(household.read_text())["robots"]
    for laser in (laser for robot in robots for laser in robot["lasers"]):
        laser["raycast"] = "march"
    (folder / "camera_calibration.yaml").symlink_to(resource("config",
                                                             "camera_calibration.yaml"))
    (folder / "worlds").mkdir()
    world = folder / "worlds" / "household_march.yaml"
    world.write_text(yaml.safe_dump({"base": str(household), "robots": robots}))
    return world


def test_tiny_navigate_run(capsys, tmp_path):
    plot = tmp_path / "nav.png"
    world = march_household(tmp_path)
    assert bench.main(["navigate", "--goals", "1", "--quiet", "--plot", str(plot),
                       "--world", str(world)]) == 0
    out = capsys.readouterr().out
    assert "goals: 1, succeeded: 1 (100.0 %), goals with a collision: 0" in out
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
