"""Grid path planning benchmark: `floorplan.astar.astar` (scipy.sparse.csgraph Dijkstra, cached
graphs and trees) against the pure-Python A* of `floorplan.tools.astar_reference`, ROS-free.

  scripts/bench_astar [--maps household,office_crossroads] [--pairs 50] [--seed 0] [--stride 10]

Three call patterns per map, each timed call by call (p50, p99, total) for both planners, with
the path lengths they find:

- `places`: every pair of places of `maps/<map>.graph.yaml` on the occupancy map with a 0.25 m
  robot radius, as `task_planner.graph.measure_edge_lengths` measures edges (skipped when the map
  has no graph);
- `replan`: the move_base mock's pattern: one goal, starts every `--stride` cells along the path
  towards it, on the map inflated by 0.4 m with a navfn-style cell penalty (cost factor 3,
  costmap_2d decay 10 /m up to 0.75 m); for the place pair with the longest route and the one
  farthest apart in a straight line (or a random connected pair when the map has no graph);
- `random`: `--pairs` independent pairs of free cells on the map inflated by 0.4 m.

The cache starts empty for each pattern, so graph building counts in the first call.
"""
import argparse
import itertools
import time

import cv2
import numpy as np

from floorplan.astar import astar, clear_path_cache, inflate_obstacles
from floorplan.tools.astar_reference import reference_astar
from floorplan.occupancy_map import load_map
from floorplan.semantic_graph import load_graph
from tamp_resources import resource

GRAPH_RADIUS = 0.25      # [m] task_planner.graph.load_graph's default robot radius
PLANNER_RADIUS = 0.4     # [m] move_base mock: robot radius 0.3 + footprint padding 0.1
INFLATION_RADIUS = 0.75  # [m] move_base mock costmap (config/nav_mocks.yaml)
COST_SCALING = 10.0      # [1/m] costmap_2d cost_scaling_factor
COST_FACTOR = 3.0        # [cells] planner cost_factor: extra length for a cell of cost 252
SAME_LENGTH = 1e-9       # [m] lengths closer than this count as equal
PLANNERS = (("reference A* (pure Python)", reference_astar), ("csgraph (floorplan.astar)", astar))


def costmap_penalty(blocked, resolution):
    """navfn-style penalty [cells of length]: COST_FACTOR * exp(-COST_SCALING (d - r)) for a free
    cell at distance d from the nearest blocked one, 0 beyond INFLATION_RADIUS - PLANNER_RADIUS
    (the move_base mock's costmap decay, measured from the inflated obstacles)."""
    distance = cv2.distanceTransform((~blocked).astype(np.uint8), cv2.DIST_L2,
                                     cv2.DIST_MASK_PRECISE) * resolution
    penalty = COST_FACTOR * np.exp(-COST_SCALING * distance)
    penalty[distance > INFLATION_RADIUS - PLANNER_RADIUS] = 0.0
    penalty[blocked] = 0.0
    return penalty


def time_calls(planner, calls):
    """(times [s], lengths [m] or None) of `planner(*args, **kwargs)` for each call, cache
    emptied first."""
    clear_path_cache()
    times, lengths = [], []
    for args, kwargs in calls:
        t0 = time.perf_counter()
        path = planner(*args, **kwargs)
        times.append(time.perf_counter() - t0)
        lengths.append(None if path is None else path.length_m)
    return times, lengths


def place_calls(grid, graph):
    """Calls for every pair of places of the graph (robot radius GRAPH_RADIUS)."""
    blocked = grid.occupied_mask()
    cells = [tuple(int(v) for v in grid.world_to_cell(*place.pose[:2])) for place in graph.places]
    return [((blocked, a, b, grid.resolution, GRAPH_RADIUS), {})
            for a, b in itertools.combinations(cells, 2)]


def random_calls(blocked, resolution, count, rng):
    """Calls for `count` pairs of free cells drawn uniformly."""
    free = np.argwhere(~blocked)
    picks = rng.integers(len(free), size=(count, 2))
    return [((blocked, tuple(free[a]), tuple(free[b]), resolution), {}) for a, b in picks]


def replan_calls(blocked, resolution, start, goal, stride):
    """Calls from every `stride`-th cell of the shortest path start -> goal to that goal, with
    the costmap penalty (the move_base mock replanning as the robot drives)."""
    penalty = costmap_penalty(blocked, resolution)
    path = reference_astar(blocked, start, goal, resolution, cell_penalty=penalty)
    if path is None:
        return []
    return [((blocked, cell, goal, resolution), {"cell_penalty": penalty})
            for cell in path.cells[:-1:stride]]


def percentile_ms(times, q):
    return 1e3 * float(np.percentile(times, q))


def report(name, calls, out=print):
    """Times both planners over `calls`; prints their figures and the length comparison.
    Returns (reference total [s], new total [s], number of lengths that differ)."""
    out(f"  {name}: {len(calls)} calls")
    results = []
    for label, planner in PLANNERS:
        times, lengths = time_calls(planner, calls)
        results.append((times, lengths))
        out(f"    {label:27s} p50 {percentile_ms(times, 50):8.2f} ms   p99 "
            f"{percentile_ms(times, 99):8.2f} ms   total {1e3 * sum(times):9.1f} ms")
    (old_times, old_lengths), (new_times, new_lengths) = results
    differ = sum(1 for a, b in zip(old_lengths, new_lengths)
                 if (a is None) != (b is None) or (a is not None and abs(a - b) > SAME_LENGTH))
    found = [a for a in old_lengths if a is not None]
    speedup = sum(old_times) / sum(new_times)
    out(f"    speed-up: total {speedup:.1f}x, p50 "
        f"{np.percentile(old_times, 50) / np.percentile(new_times, 50):.1f}x; paths found "
        f"{len(found)}/{len(calls)}, total length {sum(found):.3f} m, lengths that differ: "
        f"{differ}")
    return sum(old_times), sum(new_times), differ


def bench_map(name, pairs, seed, stride, out=print):
    """All patterns on maps/<name>.yaml, then their sum for the whole map; returns the number
    of lengths that differ."""
    grid = load_map(resource("maps", f"{name}.yaml"))
    out(f"{name}: {grid.height}x{grid.width} cells at {grid.resolution} m")
    blocked = inflate_obstacles(grid.occupied_mask(), grid.resolution, PLANNER_RADIUS)
    rng = np.random.default_rng(seed)
    graph_file = resource("maps", f"{name}.graph.yaml")
    results = []
    if graph_file.is_file():
        calls = place_calls(grid, load_graph(graph_file))
        results.append(report(f"places (every pair, robot radius {GRAPH_RADIUS} m)", calls, out))
        goals = replan_pairs(calls, blocked, grid.resolution)
    else:
        goals = [("a random connected pair", connected_pair(blocked, grid.resolution, rng))]
    for what, (start, goal) in goals:
        results.append(report(f"replan ({what}: one goal, a start every {stride} cells, cost "
                              f"penalty)",
                              replan_calls(blocked, grid.resolution, start, goal, stride), out))
    results.append(report(f"random (independent pairs, inflated by {PLANNER_RADIUS} m)",
                          random_calls(blocked, grid.resolution, pairs, rng), out))
    old, new, differ = (sum(column) for column in zip(*results))
    out(f"  {name}, all patterns: reference {1e3 * old:.1f} ms, csgraph {1e3 * new:.1f} ms, "
        f"speed-up {old / new:.1f}x, lengths that differ: {differ}")
    return differ


def connected_pair(blocked, resolution, rng, tries=100):
    """A random pair of distinct free cells joined by a path (drawn until one is)."""
    for _ in range(tries):
        (_, start, goal, _), _ = random_calls(blocked, resolution, 1, rng)[0]
        if start != goal and astar(blocked, start, goal, resolution) is not None:
            return start, goal
    raise RuntimeError(f"bench_astar: no connected pair of free cells in {tries} draws")


def replan_pairs(calls, blocked, resolution):
    """[(label, (start, goal))]: of the place pairs whose cells are free in `blocked`, the one
    with the longest route and the one farthest apart in a straight line."""
    free = [args[1:3] for args, _ in calls if not (blocked[args[1]] or blocked[args[2]])]

    def route(pair):
        path = astar(blocked, pair[0], pair[1], resolution)
        return 0.0 if path is None else path.length_m

    def straight(pair):
        return np.hypot(pair[0][0] - pair[1][0], pair[0][1] - pair[1][1])

    return [("longest route", max(free, key=route)), ("farthest apart", max(free, key=straight))]


def positive_int(text):
    value = int(text) if text.strip().isdigit() else 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer; got {text!r}")
    return value


def parser():
    p = argparse.ArgumentParser(prog="bench_astar", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--maps", default="household,office_crossroads",
                   help="comma-separated map names under maps/ (default: %(default)s)")
    p.add_argument("--pairs", type=positive_int, default=50,
                   help="random pairs per map (default: %(default)s)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default: %(default)s)")
    p.add_argument("--stride", type=positive_int, default=10,
                   help="replan every this many path cells (default: %(default)s)")
    return p


def main(argv=None):
    args = parser().parse_args(argv)
    names = [name.strip() for name in args.maps.split(",") if name.strip()]
    for name in names:
        if not resource("maps", f"{name}.yaml").is_file():
            parser().error(f"--maps: no map {name!r} under {resource('maps')}")
    differ = sum(bench_map(name, args.pairs, args.seed, args.stride) for name in names)
    return 1 if differ else 0
