"""scripts/bench_fleet's logic on a small run: every part prints every allocator's figures."""
import re

import pytest

from task_planner import bench_fleet_main as bench


def test_a_small_run_prints_every_part_and_allocator():
    lines = []
    assert bench.main(["--sets", "2", "--count", "6", "--counts", "8", "--robots", "2",
                       "--scaling-sets", "1", "--arrival-sets", "1"], out=lines.append) == 0
    text = "\n".join(lines)
    ratios = [float(v) for v in re.findall(r"exact optimum: mean ([0-9.]+)", text)]
    assert len(ratios) == len(bench.FLEET_ALLOCATORS) and max(ratios) <= 1.0 + 1e-9
    assert "[exact] 2/2" in text and "ETA 0 s" in text
    assert re.search(r"\| 8 \| 2 \| [0-9.]+, [0-9.]+ / [0-9.]+ \|", text)
    for robots in ("1 robot:", "2 robots:", "3 robots:"):
        assert robots in text


@pytest.mark.parametrize("argv, message", [
    (["--sets", "0"], "--sets: must be a positive integer; got '0'"),
    (["--robots", "2,x"], "--robots: must be positive integers separated by commas"),
    (["--count", "13"], "--count: the exact optimum takes sets of up to 12 instructions"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        bench.main(argv)
    assert message in capsys.readouterr().err
