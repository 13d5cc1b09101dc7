"""scripts/bench_human_db's library: arguments, observations, both identifications, a run."""
import numpy as np
import pytest

from human_db.tools import bench_human_db as bench
from human_db.colour import ColourIndex


@pytest.mark.parametrize("argv, message", [
    (["--people", "0"], "--people: must be a positive integer; got '0'"),
    (["--repeats", "-3"], "--repeats: must be a positive integer"),
    (["--people", "5", "--observed", "6"], "--observed (6) cannot exceed --people (5)"),
    (["--people", "1", "--observed", "1"], "--people must be at least 2"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        bench.parse_args(argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_observations_are_distinct_people_within_the_noise():
    rng = np.random.default_rng(3)
    stored = rng.integers(0, 256, size=(30, 3, 3))
    picked, observed = bench.observe(stored, 8, rng)
    assert len(set(picked.tolist())) == 8
    assert observed.min() >= 0 and observed.max() <= 255
    assert np.abs(observed - stored[picked]).max() <= bench.NOISE


def test_python_loop_agrees_with_the_vectorised_index():
    rng = np.random.default_rng(5)
    stored = rng.integers(0, 256, size=(25, 3, 3))
    names = [f"p{i}" for i in range(25)]
    picked, observed = bench.observe(stored, 5, rng)
    loop = bench.python_loop(observed.tolist(), names, stored.tolist(), bench.THRESHOLD)
    index = ColourIndex(names, stored).identify_many(observed)
    assert [m.name for m in loop] == [m.name for m in index] == [names[p] for p in picked]


def test_a_tiny_run_prints_every_figure(capsys):
    assert bench.main(["--people", "12", "--observed", "3", "--repeats", "3",
                       "--updates", "5"]) == 0
    out = capsys.readouterr().out
    assert "registered 12 people in one transaction" in out
    assert "correct matches: 3/3" in out
    assert "p50 ms    p95 ms    p99 ms" in out
    # writer 0 writes 5 updates alone, then 5 more among the 4 threads: 10 history rows
    assert "where_was over 10 history rows: p50" in out
    assert "4 writers x 5 updates" in out and "get one person with schedules: p50" in out
