"""scripts/bench_executor's library: arguments, the flood, latency lines, a tiny run."""
import random

import numpy as np
import pytest

from task_planner.tools import bench_executor as bench
from task_planner.reward import Priority


@pytest.mark.parametrize("argv, message", [
    (["--count", "0"], "--count: must be a positive integer; got '0'"),
    (["--burst", "five"], "--burst: must be a positive integer; got 'five'"),
    (["--synchronous", "full"], "--synchronous: invalid choice: 'full'"),
    (["--planner", "nope"], "--planner: invalid choice: 'nope'"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        bench.parse_args(argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_flood_launches_every_instruction_within_one_second(line_graph):
    rows = {"high": Priority("high", 8.0, 0.98), "low": Priority("low", 2.0, 0.92)}
    instructions = bench.flood(40, line_graph, rows, random.Random(1))
    assert [i.id for i in instructions] == list(range(1, 41))
    assert instructions[-1].start_time == 1.0 and instructions[0].start_time == 1 / 40
    assert {(i.gamma, i.beta) for i in instructions} <= {(8.0, 0.98), (2.0, 0.92)}
    assert {i.destination for i in instructions} <= set(range(line_graph.size))


def test_latency_line_in_ms_with_percentiles():
    seconds = np.random.default_rng(2).exponential(0.002, 30)
    ms = 1e3 * seconds
    assert bench.latency_line("per burst", seconds.tolist()) == (
        f"  per burst: p50 {np.percentile(ms, 50):.2f} ms, p95 {np.percentile(ms, 95):.2f} ms, "
        f"p99 {np.percentile(ms, 99):.2f} ms, max {ms.max():.2f} ms")
    assert bench.latency_line("none", []) == "  none: no samples"


def test_a_tiny_flood_is_journalled_and_timed(capsys):
    assert bench.main(["--count", "12", "--burst", "5", "--decisions", "4",
                       "--synchronous", "OFF"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("planner seed: 12 instructions in bursts of 5; journalled 12/12 "
                               "(synchronous=OFF)")
    assert lines[1].startswith("  per burst (journal + re-decision), 3: p50 ")
    assert lines[2].startswith("  per node step with ~12 open (decide + write back), 4: p50 ")
    assert len(lines) == 5 and all(" p99 " in line for line in lines[1:])
