"""scripts/bench_sim_node: the sim2d node's real-time factor through ROS at `speed:=0`.

Starts a roscore on a free port and, for each case, the sim2d node alone (`nodes/sim2d`) or a
whole launch file (`roslaunch tamp_bringup sim.launch speed:=0`: the node with the map_server,
AMCL and move_base mocks listening), and listens to /clock, /scan and /odom from this process
(on wall time). After `--warmup` wall seconds it counts `--seconds` more and prints, per case:
the real-time factor (sim seconds per wall second), the wall-clock rate of /scan and /odom, and
their rate in sim time (which must equal the world's laser and odometry rates at any speed).
Node-only cases also print the node's CPU share. The in-process figure of the same world
(sim2d.World stepped without ROS, as scripts/bench_sim) is measured right after each case.
"""
import argparse
import os
import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import rospkg

from tamp_bringup.bag_record import own_roscore, stop
from tamp_resources import resource

CASES = {
    # name: (world file under tamp_resources' config/worlds, launch file or None = node alone)
    "household": ("household.yaml", None),
    "office": ("office_penguin.yaml", None),
    "household_stack": ("household.yaml", "sim.launch"),
}


@dataclass
class Counter:
    """Messages of one topic seen in the measuring window, with the sim time of each."""

    wall: list = field(default_factory=list)
    sim: list = field(default_factory=list)

    def add(self, wall, sim):
        self.wall.append(wall)
        self.sim.append(sim)

    def window(self, start, end):
        return [s for w, s in zip(self.wall, self.sim) if start <= w < end]


def cpu_seconds(pid):
    """User + system CPU time of process `pid` [s] (Linux /proc/<pid>/stat)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def in_process_factor(world_file, seconds, step=0.005):
    """Real-time factor of stepping `world_file` in process for `seconds` of wall time, with
    the node's 5 ms step and its command (none: every robot stands)."""
    from sim2d.world import World
    world = World.from_file(str(world_file))
    began = time.perf_counter()
    while time.perf_counter() - began < seconds:
        for _ in range(200):
            world.step(step)
    return world.time / (time.perf_counter() - began)


class Listener:
    """/clock, /scan and /odom counted on wall time in this process (use_sim_time off)."""

    def __init__(self):
        import rospy
        from nav_msgs.msg import Odometry
        from rosgraph_msgs.msg import Clock
        from sensor_msgs.msg import LaserScan
        rospy.set_param("/use_sim_time", False)
        rospy.init_node("bench_sim_node", anonymous=True, disable_signals=True)
        self.lock = threading.Lock()
        self.topics = {}
        self.sim_now = 0.0
        rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=100)
        rospy.Subscriber("/scan", LaserScan, lambda m: self._count("scan", m), queue_size=100)
        rospy.Subscriber("/odom", Odometry, lambda m: self._count("odom", m), queue_size=100)

    def reset(self):
        with self.lock:
            self.topics = {"clock": Counter(), "scan": Counter(), "odom": Counter()}

    def _on_clock(self, msg):
        with self.lock:
            if "clock" in self.topics:
                self.topics["clock"].add(time.monotonic(), msg.clock.to_sec())

    def _count(self, name, msg):
        with self.lock:
            if name in self.topics:
                self.topics[name].add(time.monotonic(), msg.header.stamp.to_sec())

    def measure(self, warmup, seconds):
        """{factor, scan_hz, odom_hz, scan_per_sim_s, odom_per_sim_s} over the window."""
        self.reset()
        time.sleep(warmup)
        start = time.monotonic()
        time.sleep(seconds)
        end = time.monotonic()
        with self.lock:
            clock = self.topics["clock"].window(start, end)
            scan, odom = (self.topics[k].window(start, end) for k in ("scan", "odom"))
        if len(clock) < 2:
            raise RuntimeError("no /clock in the measuring window: the node did not run")
        sim_span = clock[-1] - clock[0]
        out = {"factor": sim_span / (end - start), "scan_hz": len(scan) / (end - start),
               "odom_hz": len(odom) / (end - start)}
        for name, stamps in (("scan", scan), ("odom", odom)):
            span = stamps[-1] - stamps[0] if len(stamps) > 1 else 0.0
            out[f"{name}_per_sim_s"] = (len(stamps) - 1) / span if span > 0 else 0.0
        return out


def start_case(world, launch, env, log):
    resources = resource("config", "worlds")
    if launch is None:
        node = Path(rospkg.RosPack().get_path("sim2d"), "nodes", "sim2d")
        command = [sys.executable, str(node), "__name:=sim2d", f"_world:={resources / world}",
                   "_speed:=0"]
    else:
        command = ["roslaunch", "tamp_bringup", launch, "speed:=0",
                   f"world:={resources / world}"]
    return subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT)


def run_case(name, listener, env, args, log):
    world, launch = CASES[name]
    process = start_case(world, launch, env, log)
    try:
        cpu_before = None
        if launch is None:
            time.sleep(args.warmup)
            cpu_before, wall_before = cpu_seconds(process.pid), time.monotonic()
            result = listener.measure(0.0, args.seconds)
            result["cpu"] = ((cpu_seconds(process.pid) - cpu_before)
                             / (time.monotonic() - wall_before))
        else:
            result = listener.measure(args.warmup, args.seconds)
        if process.poll() is not None:
            raise RuntimeError(f"{name}: the node exited with {process.returncode} (log: "
                               f"{log.name})")
    finally:
        stop(process)
    result["in_process"] = in_process_factor(resource("config", "worlds", world),
                                             args.in_process_seconds)
    return result


def line(name, r):
    cpu = f", node CPU {r['cpu']:.2f} cores" if "cpu" in r else ""
    return (f"{name:16s} RTF {r['factor']:6.1f} (in process {r['in_process']:6.1f}); "
            f"/scan {r['scan_hz']:6.1f} Hz = {r['scan_per_sim_s']:5.2f}/sim s; "
            f"/odom {r['odom_hz']:6.1f} Hz = {r['odom_per_sim_s']:5.2f}/sim s{cpu}")


def main(argv=None, description=None):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--seconds", type=float, default=20.0, help="measuring window [s]")
    parser.add_argument("--warmup", type=float, default=8.0,
                        help="wall seconds from start to the window (loading, range tables)")
    parser.add_argument("--in-process-seconds", type=float, default=5.0)
    args = parser.parse_args(argv)
    with own_roscore() as env:
        os.environ.update(env)   # the listener (rospy) in this process joins the same master
        listener = Listener()
        with open(Path(env["ROS_HOME"]) / "nodes.log", "w") as log:
            for name in args.cases:
                result = run_case(name, listener, env, args, log)
                print(line(name, result), flush=True)
    return 0
