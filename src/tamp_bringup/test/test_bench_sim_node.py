"""scripts/bench_sim_node's helpers (the ROS part runs in the benchmark itself)."""
import os
import time

import pytest

from tamp_bringup.tools.bench_sim_node import Counter, cpu_seconds, in_process_factor, line


def test_counter_keeps_only_the_window():
    counter = Counter()
    for wall, sim in [(1.0, 10.0), (2.0, 20.0), (3.0, 30.0), (4.0, 40.0)]:
        counter.add(wall, sim)
    assert counter.window(2.0, 4.0) == [20.0, 30.0]


def test_cpu_seconds_of_this_process_grow_with_work():
    before = cpu_seconds(os.getpid())
    end = time.process_time() + 0.2
    while time.process_time() < end:
        pass
    assert cpu_seconds(os.getpid()) - before == pytest.approx(0.2, abs=0.05)


def test_in_process_factor_steps_the_world_faster_than_real_time():
    from tamp_resources import resource
    assert in_process_factor(resource("config", "worlds") / "household.yaml", 0.3) > 5.0


def test_a_result_line_names_every_figure():
    text = line("household", dict(factor=73.9, in_process=533.0, scan_hz=739.3,
                                  scan_per_sim_s=10.0, odom_hz=3697.1, odom_per_sim_s=50.0,
                                  cpu=1.0))
    assert "RTF   73.9 (in process  533.0)" in text and "= 10.00/sim s" in text
    assert "node CPU 1.00 cores" in text
