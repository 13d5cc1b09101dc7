"""scripts/bench_task_buffer's figures: every instruction journalled, p50 <= p99 <= max."""
import argparse

import pytest

from task_planner.tools.bench_task_buffer import journal_flood, percentiles, report_lines


def test_percentiles_of_known_times():
    assert percentiles(list(range(1, 101))) == (pytest.approx(50.5), pytest.approx(99.01), 100)


@pytest.mark.parametrize("mode, calls", [("one commit each", 30), ("bursts of 8", 4)])
def test_a_flood_is_journalled_and_each_call_timed(tmp_path, mode, calls):
    figures = journal_flood(mode, 30, 8, "OFF")
    assert figures.journalled == 30 and len(figures.call_ms) == calls
    assert sum(figures.call_ms) <= 1000 * figures.elapsed_s


def test_report_lines_give_p50_p99_and_max():
    args = argparse.Namespace(count=20, burst=5, synchronous="OFF", records=200, open=3,
                              recent=10, repeats=4)
    lines = report_lines(args)
    assert len(lines) == 4
    for line in lines:
        assert " p50 " in line and ", p99 " in line and ", max " in line
    assert "journalled 20/20" in lines[0] and "journalled 20/20" in lines[1]
    assert "-> 13 instructions" in lines[2]  # 3 open + the 10 most recently finished
