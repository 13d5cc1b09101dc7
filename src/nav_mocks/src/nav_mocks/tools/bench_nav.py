"""Benchmarks of nav_mocks (issue 4), ROS-free.

  scripts/bench_nav astar [--pairs 100]        A* planning time on maps/household.yaml
  scripts/bench_nav navigate [--goals 200]     move_base core driving the sim2d world
  scripts/bench_nav places [--seeds 0,1,2]     charging place -> alley <-> dining room (its door)

`astar` times (a) the plain A* on the map inflated by the robot radius and (b) the move_base
global planner (A* on the costmap_2d-inflated costmap with its cost penalty) over random pairs of
free cells, and prints p50 / p99 / mean / max.
"""
import argparse
import statistics
import time
from pathlib import Path

import numpy as np
from floorplan.astar import astar, inflate_obstacles
from floorplan.occupancy_map import load_map
from supervision.latency import summarise
from tamp_resources import resource

from nav_mocks.costmap import Costmap
from nav_mocks.global_planner import GlobalPlanner, NoPath
from nav_mocks.move_base_core import SUCCEEDED
from nav_mocks.tools.nav_benchmark import (NavBenchConfig, load_nav_configs,
                                           run_navigation_benchmark, run_place_tour)

MAP = ("maps", "household.yaml")
GRAPH = ("maps", "household.graph.yaml")
TOUR_WORLD = ("config", "worlds", "household_no_people.yaml")  # the executor rostests'
NAV_CONFIG = ("config", "nav_mocks.yaml")


def random_pairs(blocked, count, rng):
    """`count` pairs of free cells, drawn uniformly."""
    free = np.argwhere(~blocked)
    picks = rng.integers(len(free), size=(count, 2))
    return [(tuple(free[a]), tuple(free[b])) for a, b in picks]


def summary(name, seconds):
    """One line: p50, p99, mean and max [ms] of planning times [s]."""
    ms = summarise(1e3 * s for s in seconds)
    return (f"{name}: p50 {ms.p50:.1f} ms, p99 {ms.p99:.1f} ms, mean {ms.mean:.1f} ms, "
            f"max {ms.max:.1f} ms over {ms.count} pairs")


def time_astar(blocked, pairs, resolution):
    """(times [s], paths found, lengths [m]) of the plain A* over `pairs` of cells."""
    times, found, lengths = [], 0, []
    for start, goal in pairs:
        t0 = time.perf_counter()
        path = astar(blocked, start, goal, resolution)
        times.append(time.perf_counter() - t0)
        found += path is not None
        lengths.append(path.length_m if path else 0.0)
    return times, found, lengths


def time_global_planner(planner, grid, pairs):
    """Times [s] of the move_base global planner over `pairs` of cells (no path counts too)."""
    times = []
    for start, goal in pairs:
        sx, sy = grid.cell_to_world(*start)
        gx, gy = grid.cell_to_world(*goal)
        t0 = time.perf_counter()
        try:
            planner.plan((float(sx), float(sy)), (float(gx), float(gy)))
        except NoPath:
            pass
        times.append(time.perf_counter() - t0)
    return times


def bench_astar(args):
    grid = load_map(resource(*MAP))
    rng = np.random.default_rng(args.seed)
    print(f"map {MAP[-1]}: {grid.width}x{grid.height} cells at {grid.resolution} m")
    costmap_config, _, _, planner_config, _ = load_nav_configs(resource(*NAV_CONFIG),
                                                               holonomic=True)
    radius = costmap_config.inscribed_radius
    blocked = inflate_obstacles(grid.occupied_mask(), grid.resolution, radius)
    pairs = random_pairs(blocked, args.pairs, rng)
    times, found, lengths = time_astar(blocked, pairs, grid.resolution)
    print(summary(f"A* on the map inflated by {radius:.2f} m (padded robot radius): {found} "
                  f"paths, mean length {statistics.mean(lengths):.2f} m", times))
    costmap = Costmap(grid, costmap_config)
    planner = GlobalPlanner(costmap, planner_config)
    costmap.costs()
    times = time_global_planner(planner, grid, pairs)
    print(summary(f"move_base global planner (costmap inflated to "
                  f"{costmap_config.inflation_radius} m, cost factor "
                  f"{planner_config.cost_factor})", times))
    return 0


def bench_navigate(args):
    config = NavBenchConfig(goals=args.goals, seed=args.seed, holonomic=not args.diff_drive,
                            localisation_noise=not args.true_pose)
    if args.world:
        config.world = Path(args.world)
    report = run_navigation_benchmark(config, progress=not args.quiet)
    for line in report.lines():
        print(line)
    if args.plot:
        plot_runs(report, args.plot)
        print(f"figure: {args.plot}")
    return 0 if report.success_rate >= 0.99 and report.collisions == 0 else 1


def bench_places(args):
    """The executor rostests' drives (nav_benchmark.PLACE_ROUTE) once per seed: time per leg,
    recoveries; the alley -> dining room legs (through the dining-room door) summarised."""
    door, failed = [], 0
    world = Path(args.world) if args.world else resource(*TOUR_WORLD)
    for seed in args.seeds:
        for leg in run_place_tour(NavBenchConfig(seed=seed, world=world), resource(*GRAPH)):
            o = leg.outcome
            failed += o.status != SUCCEEDED or o.bumps > 0
            print(f"seed {seed} {leg.start} -> {leg.goal}: status {o.status}, {o.seconds:.1f} s, "
                  f"{o.driven_m:.2f} m, bumps {o.bumps}, recoveries {leg.recoveries or 'none'}",
                  flush=True)
            if (leg.start, leg.goal) == ("alley", "dining_room"):
                door.append(o.seconds)
    if door:
        print(f"alley -> dining room ({len(door)} legs): median {statistics.median(door):.1f} s, "
              f"max {max(door):.1f} s; legs failed or with contact: {failed}")
    else:
        print(f"no alley -> dining room leg; legs failed or with contact: {failed}")
    return 1 if failed else 0


def plot_runs(report, path):
    """The household map with the first global plan and the driven path of each goal."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    grid = load_map(resource(*MAP))
    extent = (grid.origin[0], grid.origin[0] + grid.width * grid.resolution,
              grid.origin[1], grid.origin[1] + grid.height * grid.resolution)
    fig, ax = plt.subplots(figsize=(5, 8))
    ax.imshow(grid.occupied_mask(), origin="lower", cmap="gray_r", extent=extent)
    for i, outcome in enumerate(report.outcomes):
        colour = plt.cm.tab10(i % 10)
        if outcome.plan is not None:
            ax.plot(outcome.plan[:, 0], outcome.plan[:, 1], "--", color=colour, lw=0.8)
        if outcome.trace:
            xy = np.array(outcome.trace)
            ax.plot(xy[:, 0], xy[:, 1], "-", color=colour, lw=1.5)
            ax.plot(xy[-1, 0], xy[-1, 1], "o", color=colour, ms=4)
    ax.set_title(f"{len(report.outcomes)} goals: plan (dashed), driven (solid)")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def count(text):
    """A positive integer argument."""
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer; got {text!r}")
    return int(text)


def seed_list(text):
    """Comma-separated integer seeds, e.g. 0,1,2."""
    try:
        return [int(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"must be comma-separated integers such as 0,1,2; got {text!r}") from None


def argument_parser():
    parser = argparse.ArgumentParser(prog="bench_nav", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="what", required=True)
    a = sub.add_parser("astar")
    a.add_argument("--pairs", type=count, default=100)
    a.add_argument("--seed", type=int, default=0)
    n = sub.add_parser("navigate")
    n.add_argument("--goals", type=count, default=200)
    n.add_argument("--seed", type=int, default=0)
    n.add_argument("--diff-drive", action="store_true", help="differential drive, no lateral v")
    n.add_argument("--true-pose", action="store_true",
                   help="feed the true pose to move_base instead of the AMCL mock's estimate")
    n.add_argument("--quiet", action="store_true")
    n.add_argument("--plot", help="write a PNG of the plans and driven paths")
    n.add_argument("--world", help="sim2d world YAML (default config/worlds/household.yaml)")
    t = sub.add_parser("places")
    t.add_argument("--seeds", type=seed_list, default=[0, 1, 2],
                   help="comma-separated AMCL noise seeds, one tour each")
    t.add_argument("--world", help="sim2d world YAML (default "
                   "config/worlds/household_no_people.yaml)")
    return parser


def main(argv=None):
    args = argument_parser().parse_args(argv)
    run = {"astar": bench_astar, "navigate": bench_navigate, "places": bench_places}[args.what]
    return run(args)
