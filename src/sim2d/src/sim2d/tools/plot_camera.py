"""Render what a robot's simulated camera reports (boxes, skeletons) at a given pose and time."""
import argparse
from pathlib import Path

from tamp_resources import resource

from sim2d.camera_plot import plot_camera_frame
from sim2d.world import World

STEP_S = 0.05  # [s] simulation step while running up to --time


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="plot_camera", description=__doc__)
    parser.add_argument("--world", type=Path,
                        default=resource("config", "worlds", "household.yaml"))
    parser.add_argument("--robot", default="pepper")
    parser.add_argument("--pose", type=float, nargs=3, metavar=("X", "Y", "YAW"),
                        help="place the robot here [m, m, rad] (default: its start pose)")
    parser.add_argument("--time", type=float, default=0.0, help="simulate this long first [s]")
    parser.add_argument("--out", type=Path, required=True, help="PNG to write")
    args = parser.parse_args(argv)
    if not args.world.is_file():
        parser.error(f"--world: no such world file: {args.world}")
    if args.time < 0:
        parser.error(f"--time must not be negative; got {args.time}")
    return args


def camera_view(world, robot_name, pose=None, time_s=0.0):
    """(frame, robot) of `robot_name`'s camera after `time_s` simulated, at `pose` if given."""
    while world.time < time_s:
        world.step(STEP_S)
    try:
        robot = world.robot(robot_name)
    except KeyError:
        names = ", ".join(r.name for r in world.robots)
        raise ValueError(f"no robot named {robot_name!r} in the world (it has: {names})") \
            from None
    if pose:
        robot.state.pose = tuple(pose)
    return world.camera_frame(robot_name), robot


def main(argv=None):
    args = parse_args(argv)
    world = World.from_file(args.world)
    try:
        frame, robot = camera_view(world, args.robot, args.pose, args.time)
    except ValueError as error:
        raise SystemExit(f"plot_camera: {error}") from None
    seen = ", ".join(f"{d.truth or d.label}:{d.label}" for d in frame.objects)
    print(f"{len(frame.objects)} boxes, {len(frame.skeletons)} skeletons: {seen}")
    x, y, yaw = robot.state.pose
    plot_camera_frame(frame, title=f"{args.robot} at ({x:.1f}, {y:.1f}, {yaw:.2f}), "
                                   f"t = {world.time:.0f} s", out_path=args.out)
    return 0
