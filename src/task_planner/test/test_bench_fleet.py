"""scripts/bench_fleet's logic on a small run: every part prints every allocator's figures."""
import re

import pytest

from task_planner.tools import bench_fleet as bench


def test_a_small_run_prints_every_part_and_allocator(tmp_path):
    lines, page = [], tmp_path / "fleet.md"
    assert bench.main(["--sets", "2", "--count", "6", "--counts", "8", "--robots", "2",
                       "--scaling-sets", "1", "--arrival-sets", "1", "--seed", "3",
                       "--markdown", str(page)], out=lines.append) == 0
    text = "\n".join(lines)
    header = ("| allocator | seed 3, together: mean / worst | seed 3, staggered: mean / worst | "
              "seed 4, together: mean / worst | seed 4, staggered: mean / worst |")
    assert header in text and header in page.read_text()
    for name in bench.FLEET_ALLOCATORS:   # every ratio of the optimum at most 1
        row = re.search(rf"\| `{name}` \|(.*)\|", text).group(1)
        ratios = [float(v) for v in re.findall(r"[0-9.]+", row)]
        assert len(ratios) == 8 and max(ratios) <= 1.0 + 1e-9
    assert "[exact] 8/8" in text and "ETA 0 s" in text
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
