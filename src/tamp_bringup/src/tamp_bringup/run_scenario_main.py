"""Run a household scenario headless and write its report.

    scripts/run_scenario [SCENARIO.yaml] [--speed N] [--out-dir DIR] [--rviz]
                         [--no-self-instructions] [--no-patrol]

Defaults: config/scenarios/household_day.yaml, speed 5, docs/demo. Starts its own roscore port
and ROS_HOME (a temporary run directory, kept: the launch log, the record, the journals, a rosbag
of the run), launches `roslaunch tamp_bringup social_household.launch` with the scenario node,
waits for the scenario to end, then scripts/scenario_report writes REPORT.md and the PNGs. Run it
with the workspace environment (source scripts/env.sh).
"""
import argparse
import json
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from tamp_bringup import scenario_report_main
from tamp_bringup.scenario import load_scenario

BAG_TOPICS = ("/task_planner/instructions", "/task_planner/state", "/task_planner/markers",
              "/robot/say", "/voice_message", "/humans/known", "/base_pose_ground_truth",
              "/move_base/goal", "/move_base/result", "/clock")
STOP_TIMEOUT_S = 30.0    # [s] SIGINT grace before a child is killed
POLL_S = 0.5             # [s] period of the wait for the master


def free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def stop(process, timeout_s=STOP_TIMEOUT_S):
    """SIGINT a running child, then kill it when it has not ended within `timeout_s`."""
    if process is not None and process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout_s)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="run_scenario", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenario", nargs="?", type=Path,
                        default=Path("config/scenarios/household_day.yaml"))
    parser.add_argument("--speed", type=float, default=5.0, help="simulator speed-up")
    parser.add_argument("--out-dir", type=Path, default=Path("docs/demo"))
    parser.add_argument("--rviz", action="store_true", help="watch it in rviz")
    parser.add_argument("--no-self-instructions", action="store_true",
                        help="the robot gives itself no instructions (only the requests)")
    parser.add_argument("--no-patrol", action="store_true", help="an idle robot stays put")
    args = parser.parse_args(argv)
    if not args.speed > 0:
        parser.error(f"--speed must be positive; got {args.speed}")
    return args


def scenario_path(args):
    """The scenario file, absolute (relative paths are from the current directory)."""
    path = args.scenario if args.scenario.is_absolute() else Path.cwd() / args.scenario
    return path.resolve()


def launch_command(args, scenario, path, run_dir, port):
    """The roslaunch command line of the run."""
    command = f"scripts/run_scenario {args.scenario} --speed {args.speed:g}"
    return ["roslaunch", "-p", str(port), "tamp_bringup", "social_household.launch",
            f"speed:={args.speed:g}", f"rviz:={str(args.rviz).lower()}",
            f"planner:={scenario.planner}", f"world:={scenario.world}",
            f"run_dir:={run_dir}", f"scenario:={path}",
            f"record:={run_dir / 'record.json'}", f"command:={command}",
            f"self_instructions:={str(not args.no_self_instructions).lower()}",
            f"patrol:={str(not args.no_patrol).lower()}",
            f"utc_offset:={scenario.day_start_s:g}"]


def report_arguments(run_dir, out_dir):
    """scenario_report's arguments for the files a run leaves in `run_dir`."""
    return [str(run_dir / "record.json"), str(run_dir / "social_household_tasks.sqlite"),
            "--humans", str(run_dir / "social_household_humans.sqlite"),
            "--out-dir", str(out_dir)]


def run_launch(command, env, run_dir):
    """Run the launch to its end, recording a rosbag of the run; its exit status."""
    launch = bag = None
    try:
        with open(run_dir / "launch.log", "w") as log:
            launch = subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT)
        while launch.poll() is None and subprocess.run(
                ["rostopic", "list"], env=env, capture_output=True).returncode != 0:
            time.sleep(POLL_S)
        # a rosbag of the run: what the robot was told, decided and did (not the sensor streams)
        with open(run_dir / "rosbag.log", "w") as log:
            bag = subprocess.Popen(["rosbag", "record", "-q", "-O", str(run_dir / "run.bag"),
                                    *BAG_TOPICS, "__name:=scenario_bag"],
                                   env=env, stdout=log, stderr=subprocess.STDOUT)
        return launch.wait()
    finally:
        stop(bag)
        stop(launch)


def main(argv=None):
    args = parse_args(argv)
    path = scenario_path(args)
    scenario = load_scenario(path)
    run_dir = Path(tempfile.mkdtemp(prefix="scenario_run."))
    port = free_port()
    env = dict(os.environ, ROS_HOME=str(run_dir), ROS_LOG_DIR=str(run_dir / "log"),
               ROS_MASTER_URI=f"http://localhost:{port}")
    print(f"[scenario] {args.scenario} at speed {args.speed:g}, planner {scenario.planner} "
          f"(run directory: {run_dir})", flush=True)
    started = time.monotonic()
    status = run_launch(launch_command(args, scenario, path, run_dir, port), env, run_dir)
    print(f"[scenario] the launch ended after {time.monotonic() - started:.0f} s "
          f"(status {status})", flush=True)
    record = run_dir / "record.json"
    if not record.is_file():
        print(f"[scenario] FAILED: no record; launch log {run_dir / 'launch.log'}",
              file=sys.stderr)
        print("".join((run_dir / "launch.log").read_text().splitlines(True)[-40:]),
              file=sys.stderr)
        return 1
    if not json.loads(record.read_text())["finished"]:
        print("[scenario] the scenario timed out", file=sys.stderr)
    code = scenario_report_main.main(report_arguments(run_dir, args.out_dir))
    print(f"[scenario] run directory (launch log, record, journals, rosbag): {run_dir}")
    return code
