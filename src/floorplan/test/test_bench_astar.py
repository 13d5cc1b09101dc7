"""scripts/bench_astar's logic: both planners on the household map, figures and equal lengths."""
import pytest

from floorplan import bench_astar_main as bench


def test_household_benchmark_prints_both_planners_and_equal_lengths(capsys):
    assert bench.main(["--maps", "household", "--pairs", "3", "--stride", "40"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("household: 236x136 cells at 0.05 m")
    for pattern in ("places (every pair", "replan (longest route", "replan (farthest apart",
                    "random (independent pairs"):
        assert pattern in out
    assert out.count("reference A* (pure Python)") == 4 and out.count("p99") == 8
    assert "21 calls" in out and "3 calls" in out           # C(7, 2) place pairs, --pairs 3
    assert out.count("lengths that differ: 0") == 4


def test_a_length_that_differs_is_counted(monkeypatch):
    class Path:
        length_m = 1.0

    class Longer:
        length_m = 1.0 + 1e-6

    monkeypatch.setattr(bench, "PLANNERS", (("a", lambda *a, **k: Path()),
                                            ("b", lambda *a, **k: Longer())))
    lines = []
    _, differ = bench.report("x", [((), {}), ((), {})], lines.append)
    assert differ == 2 and "lengths that differ: 2" in lines[-1]


@pytest.mark.parametrize("argv, message", [
    (["--pairs", "0"], "--pairs: must be a positive integer; got '0'"),
    (["--maps", "nowhere"], "--maps: no map 'nowhere'"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        bench.main(argv)
    assert message in capsys.readouterr().err
