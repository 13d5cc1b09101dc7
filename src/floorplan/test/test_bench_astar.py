"""scripts/bench_astar's logic: both planners on the household map, figures and equal lengths."""
import re

import numpy as np
import pytest

from floorplan.tools import bench_astar as bench


def test_household_benchmark_prints_both_planners_and_equal_lengths(capsys):
    assert bench.main(["--maps", "household", "--pairs", "3", "--stride", "40"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("household: 236x136 cells at 0.05 m")
    for pattern in ("places (every pair", "replan (longest route", "replan (farthest apart",
                    "random (independent pairs"):
        assert pattern in out
    assert out.count("reference A* (pure Python)") == 4 and out.count("p99") == 8
    assert "21 calls" in out and "3 calls" in out           # C(7, 2) place pairs, --pairs 3
    assert out.count("lengths that differ: 0") == 5
    whole = out.splitlines()[-1]          # the map's sum over its four patterns
    assert whole.startswith("  household, all patterns: reference ")
    totals = [float(t) for t in re.findall(r"total +([0-9.]+) ms", out)]
    old, new = sum(totals[0::2]), sum(totals[1::2])      # reference, csgraph, per pattern
    shown = [float(v) for v in re.findall(r"([0-9.]+) ms", whole)]
    assert shown == pytest.approx([old, new], abs=0.21)   # each total rounded to 0.1 ms
    # The speed-up comes from the unrounded totals: it lies within the ratio the shown totals
    # allow (each +-0.05 ms), itself rounded to 0.1.
    speedup = float(re.search(r"speed-up ([0-9.]+)x", whole).group(1))
    lowest = (shown[0] - 0.05) / (shown[1] + 0.05) - 0.05
    highest = (shown[0] + 0.05) / (shown[1] - 0.05) + 0.05
    assert lowest <= speedup <= highest


def test_a_length_that_differs_is_counted(monkeypatch):
    class Path:
        length_m = 1.0

    class Longer:
        length_m = 1.0 + 1e-6

    monkeypatch.setattr(bench, "PLANNERS", (("a", lambda *a, **k: Path()),
                                            ("b", lambda *a, **k: Longer())))
    lines = []
    _, _, differ = bench.report("x", [((), {}), ((), {})], lines.append)
    assert differ == 2 and "lengths that differ: 2" in lines[-1]


@pytest.mark.parametrize("argv, message", [
    (["--pairs", "0"], "--pairs: must be a positive integer; got '0'"),
    (["--maps", "nowhere"], "--maps: no map 'nowhere'"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        bench.main(argv)
    assert message in capsys.readouterr().err


def test_connected_pair_skips_cells_that_cannot_reach_each_other():
    blocked = np.zeros((6, 9), dtype=bool)
    blocked[:, 4] = True                                   # two rooms, no door
    rng = np.random.default_rng(3)
    for _ in range(20):
        start, goal = bench.connected_pair(blocked, 1.0, rng)
        assert (start[1] < 4) == (goal[1] < 4) and start != goal   # two cells of one room
    with pytest.raises(RuntimeError, match="no connected pair"):
        bench.connected_pair(_isolated_cells(), 1.0, rng, tries=5)


def _isolated_cells():
    """A 3x3 grid whose free cells (corners) touch no other free cell, even diagonally."""
    blocked = np.ones((3, 3), dtype=bool)
    blocked[0, 0] = blocked[2, 2] = False
    return blocked
