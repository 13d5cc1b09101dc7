"""Screenshot of rviz replaying a recorded run, headless under Xvfb.

    scripts/replay_shot BAG PNG [--view VIEW] [--start S] [--after S] [--screen WxHxD]

Starts Xvfb on a free display (`-screen 0 1280x800x24`), `roslaunch tamp_bringup replay.launch
bag:=BAG view:=VIEW start:=S` on a roscore port of its own (software OpenGL), waits until rviz is
up and AFTER more seconds of wall-clock time (the bag plays meanwhile), and saves the screen with
ImageMagick's `import -window root PNG`; it prints the replayed time of the shot. Run it with the
workspace environment (source scripts/env.sh); needs the Debian packages xvfb and imagemagick.
"""
import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from tamp_bringup.bag_record import (VIEWS, RecordError, free_port, ros_tool, run_environment,
                                     sim_time_s, stop, wait_for_master, wait_until)

RVIZ_TIMEOUT_S = 60.0     # [s] wall time for rviz to register with the master


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="replay_shot", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bag", type=Path, help="recorded bag (run.bag, directions.bag)")
    parser.add_argument("png", type=Path, help="screenshot to write")
    parser.add_argument("--view", choices=VIEWS, default="social_household",
                        help="replay.launch's rviz view")
    parser.add_argument("--start", type=float, default=0.0,
                        help="start this many seconds into the bag")
    parser.add_argument("--after", type=float, default=20.0,
                        help="wall-clock seconds between rviz coming up and the shot")
    parser.add_argument("--screen", default="1280x800x24", help="Xvfb screen (W x H x depth)")
    args = parser.parse_args(argv)
    if not args.bag.is_file():
        parser.error(f"no such bag: {args.bag}")
    for program in ("Xvfb", "import"):
        if shutil.which(program) is None:
            parser.error(f"{program} not found: apt-get install xvfb imagemagick")
    return args


def free_display(first=90):
    """A display number with no X server (no /tmp/.X11-unix/X<n> nor lock file)."""
    n = first
    while Path(f"/tmp/.X11-unix/X{n}").exists() or Path(f"/tmp/.X{n}-lock").exists():
        n += 1
    return f":{n}"


def replay_command(args, port):
    return ["roslaunch", "-p", str(port), "tamp_bringup", "replay.launch",
            f"bag:={args.bag.resolve()}", f"view:={args.view}", f"start:={args.start:g}"]


def main(argv=None):
    args = parse_args(argv)
    run_dir = Path(tempfile.mkdtemp(prefix="replay_shot."))
    port, display = free_port(), free_display()
    env = dict(run_environment(run_dir, port), DISPLAY=display, LIBGL_ALWAYS_SOFTWARE="1")
    xvfb = launch = None
    try:
        with open(run_dir / "xvfb.log", "w") as log:
            xvfb = subprocess.Popen(["Xvfb", display, "-screen", "0", args.screen, "-nolisten",
                                     "tcp"], stdout=log, stderr=subprocess.STDOUT)
        with open(run_dir / "launch.log", "w") as log:
            launch = subprocess.Popen(replay_command(args, port), env=env, stdout=log,
                                      stderr=subprocess.STDOUT)
        wait_for_master(env, launch)
        wait_until(lambda: "/rviz" in (ros_tool(["rosnode", "list"], env) or "").split(), launch,
                   RVIZ_TIMEOUT_S, "rviz")
        time.sleep(args.after)
        replayed = sim_time_s(env)
        args.png.parent.mkdir(parents=True, exist_ok=True)
        subprocess.run(["import", "-window", "root", str(args.png)], env=env, check=True)
    except (RecordError, subprocess.CalledProcessError) as error:
        print(f"[replay_shot] {error}; logs in {run_dir}", file=sys.stderr)
        return 1
    finally:
        stop(launch)
        stop(xvfb, timeout_s=5.0)
    at = f"{replayed:.1f} s" if replayed is not None else "an unknown time"
    print(f"[replay_shot] {args.png} at {at} of replayed time ({args.view}; logs in {run_dir})")
    return 0
