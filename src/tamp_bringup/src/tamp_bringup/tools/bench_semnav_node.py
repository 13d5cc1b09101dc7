"""scripts/bench_semnav_node: the semantic_nav node's start time and memory.

Starts a roscore on a free port, then the node (`nodes/semantic_nav`, default model and GloVe
cache) `--runs` times, each until it logs "semantic_nav: ready"; prints the time from process
start to that line and the node's resident memory (VmRSS) a second later, p50 and max over the
runs.
"""
import argparse
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import rospkg

from tamp_bringup.bag_record import own_roscore

READY = "semantic_nav: ready"


def rss_mib(pid):
    """Resident memory of process `pid` [MiB] (Linux /proc)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    raise RuntimeError(f"no VmRSS for process {pid}")


def start_once(node, env, timeout):
    """(seconds from process start to the ready line, RSS [MiB] a second later)."""
    began = time.perf_counter()
    process = subprocess.Popen([sys.executable, str(node), "__name:=semantic_nav"], env=env,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        for line in process.stdout:
            if READY in line:
                ready = time.perf_counter() - began
                time.sleep(1.0)
                return ready, rss_mib(process.pid)
            if time.perf_counter() - began > timeout:
                break
        raise RuntimeError(f"the node did not log {READY!r} within {timeout} s")
    finally:
        process.terminate()
        process.wait(10)


def main(argv=None, description=None):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--timeout", type=float, default=60.0, help="per start [s]")
    args = parser.parse_args(argv)
    node = Path(rospkg.RosPack().get_path("semantic_nav"), "nodes", "semantic_nav")
    with own_roscore() as env:
        runs = [start_once(node, env, args.timeout) for _ in range(args.runs)]
    starts, memory = np.array([r[0] for r in runs]), np.array([r[1] for r in runs])
    print(f"semantic_nav node, {args.runs} starts: ready after p50 {np.median(starts):.2f} s, "
          f"max {starts.max():.2f} s; RSS p50 {np.median(memory):.0f} MiB, "
          f"max {memory.max():.0f} MiB")
    return 0
