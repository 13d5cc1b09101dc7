"""Record a direction-following episode as a rosbag that rviz replays.

    scripts/record_directions [TEXT] [--floor FLOOR] [--laser LASER] [--speed N]
                              [--timeout S] [--out-dir DIR] [--rviz]

Starts `roslaunch tamp_bringup semantic_nav.launch` (the simulated Penguin on a test floor and the
semantic_nav node) on its own roscore port with ROS_HOME DIR/run, records directions.bag (tf,
laser, odometry, the driven path and doorway markers, the goal, feedback and result of the
follow_directions action; no /clock) while the robot follows TEXT (default "go straight to the
end, then turn left") from the world's start pose, prints a progress line every 10 s, and stops
when the action ends or TIMEOUT seconds of simulated time have passed. Default DIR: the run
folder build/directions/<UTC time>/ of the workspace. Replay:
`roslaunch tamp_bringup replay.launch bag:=DIR/directions.bag view:=semantic_nav`.
Run it with the workspace environment (source scripts/env.sh).
"""
import argparse
import subprocess
import sys
import time
from pathlib import Path

from tamp_bringup.bag_record import (DIRECTIONS_TOPICS, RecordError, free_port, replay_command,
                                     run_environment, save_robot_description, start_recorder,
                                     stop, wait_for_master, wait_for_recording,
                                     wait_for_sim_time)
from tamp_bringup.tools.run_scenario import default_out_dir

SENTENCE = "go straight to the end, then turn left"
BAG_NAME = "directions.bag"
SERVER_TIMEOUT_S = 120.0   # [s] wall time for the node to load its network and serve


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="record_directions", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("text", nargs="?", default=SENTENCE, help="the direction to follow")
    parser.add_argument("--floor", default="office_ring",
                        help="test floor of semantic_nav.launch (office_ring, office_comb, "
                             "office_wings)")
    parser.add_argument("--laser", default="utm30lx", help="utm30lx or urg04lx")
    parser.add_argument("--speed", type=float, default=2.0, help="simulator speed-up")
    parser.add_argument("--timeout", type=float, default=240.0,
                        help="give up after this much simulated time [s]")
    parser.add_argument("--out-dir", type=Path, default=None,
                        help="run folder (default: build/directions/<UTC time>/)")
    parser.add_argument("--rviz", action="store_true", help="watch it in rviz while it runs")
    args = parser.parse_args(argv)
    if not args.speed > 0:
        parser.error(f"--speed must be positive; got {args.speed}")
    if not args.timeout > 0:
        parser.error(f"--timeout must be positive; got {args.timeout}")
    args.out_dir = (args.out_dir or default_out_dir("directions")).resolve()
    return args


def launch_command(args, port):
    """The roslaunch command line of the episode."""
    return ["roslaunch", "-p", str(port), "tamp_bringup", "semantic_nav.launch",
            f"floor:={args.floor}", f"laser:={args.laser}", f"speed:={args.speed:g}",
            f"rviz:={str(args.rviz).lower()}"]


def client_command(args):
    """The action client that sends the direction and reports on it (ros_directions_client)."""
    return [sys.executable, "-m", "tamp_bringup.ros_directions_client", args.text,
            "--timeout", f"{args.timeout:g}", "--server-timeout", f"{SERVER_TIMEOUT_S:g}"]


def run(args, run_dir, bag):
    """Launch, record and follow; the client's exit status (0: the direction was followed)."""
    port = free_port()
    env = run_environment(run_dir, port)
    launch = recorder = None
    log_path = run_dir / "launch.log"
    try:
        with open(log_path, "w") as log:
            launch = subprocess.Popen(launch_command(args, port), env=env, stdout=log,
                                      stderr=subprocess.STDOUT)
        wait_for_master(env, launch)
        wait_for_sim_time(env, launch)
        recorder = start_recorder(bag, DIRECTIONS_TOPICS, env, run_dir / "rosbag.log")
        wait_for_recording(env, recorder, "/scan")   # the drive starts only once it is recorded
        save_robot_description(bag, env)
        return subprocess.run(client_command(args), env=env).returncode
    except RecordError as error:
        print(f"[directions] {error}; launch log {log_path}", file=sys.stderr)
        return 3
    finally:
        stop(recorder)
        stop(launch)


def main(argv=None):
    args = parse_args(argv)
    run_dir = args.out_dir / "run"
    run_dir.mkdir(parents=True, exist_ok=True)
    bag = args.out_dir / BAG_NAME
    print(f"[directions] \"{args.text}\" on {args.floor} ({args.laser}) at speed "
          f"{args.speed:g}, at most {args.timeout:g} s simulated; run folder {args.out_dir}",
          flush=True)
    started = time.monotonic()
    status = run(args, run_dir, bag)
    print(f"[directions] ended after {time.monotonic() - started:.0f} s (status {status}); "
          f"launch log {run_dir / 'launch.log'}", flush=True)
    if not bag.is_file():
        print(f"[directions] no rosbag was written; see {run_dir / 'rosbag.log'}",
              file=sys.stderr)
        return 1
    print(f"[directions] bag: {bag}")
    print(f"[directions] replay in rviz: {replay_command(bag, 'semantic_nav')}")
    return status
