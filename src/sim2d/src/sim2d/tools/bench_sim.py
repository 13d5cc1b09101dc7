"""Benchmark sim2d in-process (no ROS): real-time factor of stepping the simulated worlds.

1. Penguin + Hokuyo UTM-30LX (1081 beams at 40 Hz, per-cell range table) on an office floor,
   stepped at the scan period while a reactive controller steers toward open space.
2. The household: Pepper (holonomic, 45-beam laser), 4 people following their schedules,
   30+ objects, camera detections at the configured camera rate.
Also: accuracy of the range table against exact ray marching on the same floor. Step times are
reported as mean, p50 and p99 [us].
--crowd instead: 1, 4 and 8 Penguins with 0, 10 and 20 walking people on the largest floor
(sim2d.tools.bench_crowd), each with the windowed overlay of robots and people, the lasers cast
together and one by one, and one by one with every beam cast against every robot and person.
Prints the figures; --plot writes the Penguin's path over the map as a PNG.
"""
import argparse
import json
import math
import os
import time
from pathlib import Path

import numpy as np
from floorplan.plotting import plot_map
from floorplan.semantic_graph import load_graph
from supervision.latency import percentile
from tamp_resources import resource

from sim2d.tools.bench_crowd import bench_crowds
from sim2d.raycast import RangeTable, ray_march
from sim2d.world import World

STEER_GAIN = 1.2        # [1/s] angular speed per radian of bearing to the most open direction
CRUISE = 0.35           # [m/s]
SLOW_RANGE = 0.6        # [m] stop and turn when the way ahead is closer than this
FRONT_HALF_ANGLE = 0.8  # [rad] half-width of the sector that counts as "ahead"
TURN_IN_PLACE = 0.8     # [rad/s]
HOUSEHOLD_DT = 0.025    # [s] household simulation step
SCAN_POSE = (15.0, 10.0, 0.0)  # [m, m, rad] the office floor's crossroad, facing east


def steer(ranges, angles):
    """Reactive controller: drive toward the most open direction of the scan (v, w)."""
    finite = np.where(np.isfinite(ranges), ranges, 30.0)
    smooth = np.convolve(finite, np.ones(31) / 31.0, mode="same")
    bearing = float(angles[int(np.argmax(smooth))])
    front = np.abs(angles) < FRONT_HALF_ANGLE
    ahead = float(finite[front].min())
    if ahead < SLOW_RANGE:
        return 0.0, TURN_IN_PLACE        # blocked: turn left on the spot until the way is free
    return CRUISE, max(-1.0, min(1.0, STEER_GAIN * bearing))


def shown(path):
    """A world path as printed: relative to tamp_resources when it is one of its files."""
    try:
        return str(Path(path).relative_to(resource()))
    except ValueError:
        return str(path)


def step_figures(sim_seconds, steps, step_us):
    """Real-time factor and per-step wall time (mean, p50, p99 [us]) of `steps` timed steps."""
    wall = sum(step_us) / 1e6
    return dict(sim_seconds=sim_seconds, steps=steps, wall_seconds=wall,
                real_time_factor=sim_seconds / wall, us_per_step=wall / steps * 1e6,
                step_p50_us=percentile(step_us, 50), step_p99_us=percentile(step_us, 99))


def bench_penguin(world_file, seconds):
    """(figures, world, path) of the Penguin driven by `steer` for `seconds` simulated."""
    t0 = time.perf_counter()
    world = World.from_file(world_file)
    setup = time.perf_counter() - t0
    robot = world.robots[0]
    laser = robot.lasers[0]
    dt = laser.model.scan_time
    steps = max(1, int(round(seconds / dt)))
    path = np.empty((steps, 2))
    clock, cpu_clock = time.perf_counter, time.process_time
    step_us, cpu = [], 0.0            # wall and CPU time spent inside world.step only
    t_loop = clock()
    for k in range(steps):
        t0, c0 = clock(), cpu_clock()
        world.step(dt)
        step_us.append((clock() - t0) * 1e6)
        cpu += cpu_clock() - c0
        v, w = steer(robot.scans[0].ranges, laser.angles)
        world.set_twist(robot.name, v, 0.0, w)
        path[k] = robot.state.pose[:2]
    loop = clock() - t_loop
    figures = dict(world=shown(world_file), **step_figures(steps * dt, steps, step_us),
                   cpu_seconds=cpu, real_time_factor_cpu=steps * dt / max(cpu, 1e-9),
                   loop_with_controller_seconds=loop,
                   real_time_factor_with_controller=steps * dt / loop,
                   scans=robot.scans[0].count, beams=laser.model.num_beams,
                   bumps=robot.state.bumps, setup_seconds=setup,
                   raycast="table" if laser.table is not None else "march",
                   distance_m=float(np.sum(np.hypot(*np.diff(path, axis=0).T))))
    return figures, world, path


def table_accuracy(world, samples, seed=0):
    """|table - exact| over random tabulated poses and full UTM-30LX scans."""
    laser = world.robots[0].lasers[0]
    table, rng = laser.table, np.random.default_rng(seed)
    grid = world.grid
    errors = []
    while len(errors) < samples:
        x = rng.uniform(grid.origin[0], grid.origin[0] + grid.width * grid.resolution)
        y = rng.uniform(grid.origin[1], grid.origin[1] + grid.height * grid.resolution)
        yaw = rng.integers(0, table.config.angle_bins) * table.bin_width
        angles = yaw + laser.angles
        fast = table.cast(x, y, angles)
        if fast is None:
            continue
        exact = ray_march(world.geometry, x, y, angles, laser.model.range_max)
        ok = np.isfinite(exact)
        errors.append(np.abs(fast[ok] - exact[ok]))
    e = np.concatenate(errors)
    return dict(scans=samples, beams=int(e.size), median_mm=float(np.median(e) * 1e3),
                p90_mm=float(np.percentile(e, 90) * 1e3), p99_mm=float(np.percentile(e, 99) * 1e3),
                share_over_5cm=float((e > 0.05).mean()))


def bench_build(world, repeats=20):
    """Fresh range-table build (no cache) and exact ray marching of one full scan."""
    laser = world.robots[0].lasers[0]
    t0 = time.perf_counter()
    table = RangeTable.build(world.geometry, laser.table.config, cache_dir=None)
    build = time.perf_counter() - t0
    angles = laser.angles + 0.3
    scan_ms = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        ray_march(world.geometry, *SCAN_POSE[:2], angles, laser.model.range_max)
        scan_ms.append((time.perf_counter() - t0) * 1e3)
    march = sum(scan_ms) / repeats / 1e3
    return dict(table_points=int(table.table.shape[0]), table_bins=int(table.table.shape[1]),
                table_megabytes=table.table.nbytes / 1e6, table_build_seconds=build,
                table_rays_per_second=table.table.size / build,
                exact_scan_ms=march * 1e3, exact_scan_p50_ms=percentile(scan_ms, 50),
                exact_scan_p99_ms=percentile(scan_ms, 99),
                exact_rays_per_second=angles.size / march)


def bench_household(world_file, seconds, dt=HOUSEHOLD_DT):
    """Figures of the household world stepped for `seconds`, with camera frames at its rate."""
    t0 = time.perf_counter()
    world = World.from_file(world_file)
    setup = time.perf_counter() - t0
    robot = world.robots[0]
    period = 1.0 / robot.config.camera.rate
    steps = max(1, int(round(seconds / dt)))
    next_frame, frames, detections, step_us = 0.0, 0, 0, []
    for k in range(steps):
        t0 = time.perf_counter()
        world.set_twist(robot.name, 0.0, 0.0, 0.4 * math.sin(0.05 * k * dt))
        world.step(dt)
        if world.time >= next_frame:
            frame = world.camera_frame(robot.name)
            frames += 1
            detections += len(frame.objects)
            next_frame += period
        step_us.append((time.perf_counter() - t0) * 1e6)
    return dict(world=shown(world_file), **step_figures(steps * dt, steps, step_us),
                people=len(world.people), objects=len(world.objects), camera_frames=frames,
                detections=detections, scans=robot.scans[0].count, setup_seconds=setup)


def positive(text):
    value = float(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be a positive number; got {text!r}")
    return value


def parse_args(argv=None):
    worlds = resource("config", "worlds")
    parser = argparse.ArgumentParser(prog="bench_sim", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seconds", type=positive, default=120.0,
                        help="simulated seconds per run")
    parser.add_argument("--penguin-world", type=Path, default=worlds / "office_penguin.yaml")
    parser.add_argument("--household-world", type=Path, default=worlds / "household.yaml")
    parser.add_argument("--accuracy-scans", type=int, default=200)
    parser.add_argument("--build-table", action="store_true",
                        help="also time building the Penguin floor's range table from scratch "
                             "and one exact ray-marched scan")
    parser.add_argument("--crowd", action="store_true",
                        help="only the crowded-world table (robots x people, two overlays)")
    parser.add_argument("--crowd-world", type=Path,
                        default=worlds / "semnav_office_wings_urg04lx.yaml",
                        help="world whose map and first robot the crowds copy (default: "
                             "office_wings, 44 x 30 m, the Penguin with a URG-04LX)")
    parser.add_argument("--json", type=Path, help="also write the figures here")
    parser.add_argument("--plot", type=Path, help="PNG of the Penguin's path over the map")
    parser.add_argument("--scan-plot", type=Path,
                        help="PNG of one UTM-30LX scan taken at the floor's crossroad")
    args = parser.parse_args(argv)
    if args.accuracy_scans < 1:
        parser.error(f"--accuracy-scans must be at least 1; got {args.accuracy_scans}")
    for option in ("penguin_world", "household_world", "crowd_world"):
        if not getattr(args, option).is_file():
            parser.error(f"--{option.replace('_', '-')}: no such world file: "
                         f"{getattr(args, option)}")
    return args


def crowd_main(args):
    """The --crowd table: real-time factor of world.step per robots x people."""
    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores; "
          f"{shown(args.crowd_world)}, {args.seconds:.0f} s simulated per run")
    print("robots  people  windowed  one by one  every beam  speed-up  scans")
    rows = []
    for row in bench_crowds(args.crowd_world.resolve(), steer, args.seconds):
        rows.append(row)
        print(f"{row['robots']:6d}  {row['people']:6d}  {row['windowed']:7.0f}x  "
              f"{row['one_by_one']:9.0f}x  {row['every_beam']:9.0f}x  "
              f"{row['windowed'] / row['every_beam']:7.2f}x  {row['scans']:5d}", flush=True)
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    if args.json:
        args.json.write_text(json.dumps(dict(world=shown(args.crowd_world),
                                             sim_seconds=args.seconds, crowds=rows),
                                        indent=2) + "\n")
    return 0


def main(argv=None):
    args = parse_args(argv)
    if args.crowd:
        return crowd_main(args)
    print(f"load average before: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    penguin, world, path = bench_penguin(args.penguin_world.resolve(), args.seconds)
    print("penguin  :", json.dumps(penguin))
    accuracy = table_accuracy(world, args.accuracy_scans)
    print("table    :", json.dumps(accuracy))
    household = bench_household(args.household_world.resolve(), args.seconds)
    print("household:", json.dumps(household))
    build = bench_build(world) if args.build_table else {}
    if build:
        print("build    :", json.dumps(build))
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print(f"\nreal-time factor: penguin {penguin['real_time_factor']:.0f}x, "
          f"household {household['real_time_factor']:.0f}x")
    print(f"step time: penguin p50 {penguin['step_p50_us']:.0f} us, p99 "
          f"{penguin['step_p99_us']:.0f} us; household p50 {household['step_p50_us']:.0f} us, "
          f"p99 {household['step_p99_us']:.0f} us")
    if args.json:
        args.json.write_text(json.dumps(dict(penguin=penguin, table_accuracy=accuracy,
                                             household=household, build=build),
                                        indent=2) + "\n")
    if args.plot:
        graph_file = world.config.graph_path
        plot_map(world.grid, load_graph(graph_file) if graph_file else None,
                 paths=[("penguin, reactive controller", path)],
                 title=f"{penguin['sim_seconds']:.0f} s simulated in "
                       f"{penguin['wall_seconds']:.2f} s", out_path=args.plot)
    if args.scan_plot:
        plot_scan(world, args.scan_plot)
    return 0


def plot_scan(world, out_path):
    """One noisy scan from the crossroad, facing east, drawn as returns over the map."""
    robot, laser = world.robots[0], world.robots[0].lasers[0]
    ranges = laser.scan(SCAN_POSE)
    lx, ly, lyaw = laser.pose_in_map(SCAN_POSE)
    ok = np.isfinite(ranges)
    xy = np.column_stack([lx + ranges[ok] * np.cos(laser.angles[ok] + lyaw),
                          ly + ranges[ok] * np.sin(laser.angles[ok] + lyaw)])
    heading = np.array([SCAN_POSE[:2], (SCAN_POSE[0] + 1.0, SCAN_POSE[1])])
    plot_map(world.grid, None, paths=[("robot heading", heading)],
             points=[(f"{laser.model.name} returns ({ok.sum()} of {ranges.size})", xy)],
             title=f"{robot.name} at the crossroad, one scan", out_path=out_path)
