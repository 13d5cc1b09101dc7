"""Run a household scenario headless, record it and write its report.

    scripts/run_scenario [SCENARIO.yaml] [--speed N] [--out-dir DIR] [--run-dir DIR] [--rviz]
                         [--no-self-instructions] [--no-patrol] [--fleet [--pool URL]]

Defaults: config/scenarios/household_day.yaml, speed 5, the run folder
build/scenario/<UTC time>/ of the workspace. Starts its own roscore port and ROS_HOME (the run
directory, DIR/run unless --run-dir: the launch log, the record, the journals, the logs and
run.bag, a rosbag of the run that `roslaunch tamp_bringup replay.launch bag:=.../run.bag` replays
in rviz; an earlier run's files there are removed first, and a folder holding other files is
refused), launches `roslaunch tamp_bringup social_household.launch` with the scenario node
and no shirt in human_db (the robot meets each resident and asks who they are, §3.2.3),
prints a progress line with an ETA every 10 s until the scenario ends, then writes REPORT.md and
the PNGs as scripts/scenario_report does. With --fleet the same people and requests are served
by two robots (`household_fleet.launch` on config/worlds/household_fleet.yaml), and the report
reads both robots' journals; their pool is an SQLite file in the run folder, or the PostgreSQL
database --pool names (postgresql://[user@]host[:port]/db, an empty database). Run it with the
workspace environment (source scripts/env.sh).
"""
import argparse
import json
import shutil
import subprocess
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

from task_planner.fleet_pool_db import without_password
from tamp_resources import resource, workspace

from tamp_bringup.tools import scenario_report
from tamp_bringup.bag_record import (SCENARIO_TOPICS, RecordError, free_port, run_environment,
                                     save_robot_description, sim_time_s, start_recorder, stop,
                                     wait_for_master, wait_for_recording, wait_for_sim_time)
from tamp_bringup.progress import SimRate, count_sent_requests, scenario_line
from tamp_bringup.scenario import load_scenario

PROGRESS_S = 10.0        # [s] wall-clock period of the progress lines
BAG_NAME = "run.bag"


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="run_scenario", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scenario", nargs="?", type=Path,
                        default=Path("config/scenarios/household_day.yaml"))
    parser.add_argument("--speed", type=float, default=5.0, help="simulator speed-up")
    parser.add_argument("--out-dir", type=Path, default=None,
                        help="where REPORT.md and its plots go (default: a new run folder "
                             "build/scenario/<UTC time>/ of the workspace)")
    parser.add_argument("--run-dir", type=Path, default=None,
                        help="ROS_HOME of the run: launch log, record, journals, logs, run.bag "
                             "(default: OUT_DIR/run)")
    parser.add_argument("--rviz", action="store_true", help="watch it in rviz")
    parser.add_argument("--no-self-instructions", action="store_true",
                        help="the robot gives itself no instructions (only the requests)")
    parser.add_argument("--no-patrol", action="store_true", help="an idle robot stays put")
    parser.add_argument("--fleet", action="store_true",
                        help="two robots serve the scenario (household_fleet.launch on "
                             "config/worlds/household_fleet.yaml) instead of the scenario's one")
    parser.add_argument("--pool", default=None,
                        help="with --fleet: the fleet pool, postgresql://[user@]host[:port]/db "
                             "(an empty database; default an SQLite file in the run folder)")
    args = parser.parse_args(argv)
    if args.pool is not None and not args.fleet:
        parser.error("--pool needs --fleet")
    if args.pool is not None and not args.pool.startswith("postgresql://"):
        parser.error(f"--pool must be a postgresql:// URL; got {args.pool!r}")
    if not args.speed > 0:
        parser.error(f"--speed must be positive; got {args.speed}")
    if args.out_dir is None:
        args.out_dir = default_out_dir("scenario")
    if args.run_dir is None:
        args.run_dir = args.out_dir / "run"
    args.out_dir, args.run_dir = args.out_dir.resolve(), args.run_dir.resolve()
    return args


def default_out_dir(kind, now=None):
    """build/<kind>/<UTC time>/ of the workspace (tamp_resources.workspace())."""
    now = now or datetime.now(UTC)
    return workspace() / "build" / kind / now.strftime("%Y%m%d-%H%M%S")


def scenario_path(args):
    """The scenario file, absolute (relative paths are from the current directory)."""
    path = args.scenario if args.scenario.is_absolute() else Path.cwd() / args.scenario
    return path.resolve()


def launch_command(args, scenario, path, run_dir, port):
    """The roslaunch command line of the run."""
    pool = without_password(args.pool) if args.pool else ""
    command = f"scripts/run_scenario {args.scenario} --speed {args.speed:g}" + (
        " --fleet" if args.fleet else "") + (f" --pool {pool}" if pool else "")
    launch, world = (("household_fleet.launch", resource("config", "worlds",
                                                          "household_fleet.yaml"))
                     if args.fleet else ("social_household.launch", scenario.world))
    return ["roslaunch", "-p", str(port), "tamp_bringup", launch,
            f"speed:={args.speed:g}", f"rviz:={str(args.rviz).lower()}",
            f"planner:={scenario.planner}", f"world:={world}",
            f"run_dir:={run_dir}", f"scenario:={path}",
            f"record:={run_dir / 'record.json'}", f"command:={command}",
            f"self_instructions:={str(not args.no_self_instructions).lower()}",
            f"patrol:={str(not args.no_patrol).lower()}",
            f"utc_offset:={scenario.day_start_s:g}",
            "shirts:=none"] + (   # nobody met: the robot asks each resident who they are
        [f"pool:={args.pool}"] if args.pool else [])


def report_arguments(run_dir, out_dir, bag=None, fleet=False):
    """scenario_report's arguments for the files a run leaves in `run_dir`."""
    journals = ([run_dir / f"{robot}_task_buffer.sqlite" for robot in ("robot1", "robot2")]
                if fleet else [run_dir / "social_household_tasks.sqlite"])
    humans = "household_fleet_humans.sqlite" if fleet else "social_household_humans.sqlite"
    arguments = [str(run_dir / "record.json")] + [str(j) for j in journals] + [
        "--humans", str(run_dir / humans), "--out-dir", str(out_dir)]
    return arguments + (["--bag", str(bag)] if bag is not None else [])


def watch(launch, env, scenario, speed, log_path, started, period_s=PROGRESS_S):
    """Wait for the launch to end, printing a progress line every `period_s`; its status."""
    rate = SimRate(speed)
    last_request = max(r.time_s for r in scenario.requests)
    while True:
        try:
            return launch.wait(period_s)
        except subprocess.TimeoutExpired:
            pass
        wall = time.monotonic() - started
        sim = sim_time_s(env)
        sent = count_sent_requests(log_path.read_text(errors="replace"))
        started_sim = rate.first is not None
        print(scenario_line(wall, sim, rate.update(wall, sim) if sim is not None else speed,
                            last_request, scenario.timeout_s, len(scenario.requests), sent,
                            started_sim), flush=True)


def run_launch(command, env, run_dir, scenario, speed, started):
    """Run the launch to its end, recording a rosbag of the run; its exit status."""
    launch = bag = None
    log_path = run_dir / "launch.log"
    try:
        with open(log_path, "w") as log:
            launch = subprocess.Popen(command, env=env, stdout=log, stderr=subprocess.STDOUT)
        wait_for_master(env, launch)
        wait_for_sim_time(env, launch)
        bag = start_recorder(run_dir / BAG_NAME, SCENARIO_TOPICS, env, run_dir / "rosbag.log")
        wait_for_recording(env, bag, "/tf")   # every run has it (a fleet's scans are
        #                                        /robot1/scan, /robot2/scan)
        save_robot_description(run_dir / BAG_NAME, env)
        return watch(launch, env, scenario, speed, log_path, started)
    except RecordError as error:
        print(f"[scenario] {error}; launch log {log_path}", file=sys.stderr)
        return launch.poll() if launch.poll() is not None else 1
    finally:
        stop(bag)
        stop(launch)


RUN_FILES = ("*.sqlite", "*.sqlite-shm", "*.sqlite-wal", "record.json", "record.json.partial",
             "launch.log", "rosbag.log", "run.bag", "run.bag.active", "run.urdf",
             "rospack_cache_*")


def fresh_run_dir(run_dir):
    """Make `run_dir` empty for a new run: an earlier run's files there (journals, fleet pool,
    people database, record, logs, bag) are removed, as the new day must not start from the old
    one's instructions. A folder that holds anything else is refused (ValueError naming it)."""
    run_dir.mkdir(parents=True, exist_ok=True)
    run_files = {p for pattern in RUN_FILES for p in run_dir.glob(pattern)}
    others = sorted(p.name for p in run_dir.iterdir()
                    if p not in run_files and not (p.name == "log" and p.is_dir()))
    if others:
        raise ValueError(f"--run-dir {run_dir} holds files no run writes ({', '.join(others[:5])}"
                         f"{', ...' if len(others) > 5 else ''}): give an empty or new folder")
    for path in run_files:
        path.unlink()
    shutil.rmtree(run_dir / "log", ignore_errors=True)


def main(argv=None):
    args = parse_args(argv)
    path = scenario_path(args)
    scenario = load_scenario(path)
    run_dir = args.run_dir
    try:
        fresh_run_dir(run_dir)
    except ValueError as error:
        print(f"[scenario] {error}", file=sys.stderr)
        return 2
    port = free_port()
    env = run_environment(run_dir, port)
    last_request = max(r.time_s for r in scenario.requests)
    print(f"[scenario] {args.scenario} at speed {args.speed:g}, planner {scenario.planner}: "
          f"{len(scenario.requests)} requests by {last_request:g} s simulated, done when they "
          f"are served (at most {last_request + scenario.timeout_s:g} s simulated); "
          f"run directory {run_dir}", flush=True)
    started = time.monotonic()
    status = run_launch(launch_command(args, scenario, path, run_dir, port), env, run_dir,
                        scenario, args.speed, started)
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
    bag = run_dir / BAG_NAME
    code = scenario_report.main(
        report_arguments(run_dir, args.out_dir, bag if bag.is_file() else None, args.fleet))
    print(f"[scenario] run directory (launch log, record, journals, rosbag): {run_dir}")
    if not bag.is_file():
        print(f"[scenario] no rosbag was written; see {run_dir / 'rosbag.log'}", file=sys.stderr)
    return code
