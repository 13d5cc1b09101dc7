"""scripts/bench_semnav_node's helpers."""
import os

from tamp_bringup.bag_record import free_port
from tamp_bringup.tools.bench_semnav_node import rss_mib


def test_node_bench_helpers_measure_this_process():
    assert 20 < rss_mib(os.getpid()) < 4096
    assert 1024 <= free_port() <= 65535
