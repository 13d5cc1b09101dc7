"""Command line of scripts/plot_semnav_oracle: the route oracle's goal of every instruction class
from the annotated starts of each floor, and each floor's corridor structure, as PNG files."""
import argparse
import math
from pathlib import Path

import numpy as np
import rospkg
import yaml

from floorplan.occupancy_map import load_map
from semantic_nav.instruction_classes import CLASS_IDS, NAMES, NUM_CLASSES
from semnav_learning.demonstrations import floor_map_path
from semnav_learning.floor_structure import floor_structure, sample_corridor_starts
from semnav_learning.oracle_plot import plot_floor_structure, plot_oracle_goals
from semnav_learning.route_oracle import RouteOracle
from tamp_resources import resource, workspace

STRUCTURE_STARTS = 20     # sampled starts drawn on each structure picture


def argument_parser(description=None):
    """The options of plot_semnav_oracle; the starts default to this package's fixture, the
    output to the workspace's docs/."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--starts", type=Path, default=Path(
        rospkg.RosPack().get_path("semnav_learning"), "fixtures", "oracle_expected_goals.yaml"))
    parser.add_argument("--out", type=Path, default=workspace() / "docs" / "semantic_nav" /
                        "oracle")
    return parser


def shown(path, root):
    """`path` relative to the workspace `root` where it lies inside it, else as it is."""
    try:
        return Path(path).relative_to(root)
    except ValueError:
        return path


def plot_start_goals(floor, grid, oracle, number, entry, out):
    """The goal picture of one annotated start ({"start": [x, y, yaw°]}) -> (path, number of
    classes applicable)."""
    x, y, yaw = entry["start"]
    start = (x, y, math.radians(yaw))
    walk = oracle.walk(start)
    goals = {label: oracle.goal(start, label, walk) for label in CLASS_IDS}
    path = out / f"{floor}_{number}.png"
    plot_oracle_goals(grid, start, walk, goals,
                      f"{floor}: start {number} ({x:.1f}, {y:.1f}, {yaw:.0f}°)", path, NAMES)
    return path, sum(goal is not None for goal in goals.values())


def plot_structure(floor, grid, oracle, out):
    """The corridor-structure picture of one floor -> (path, FloorStructure)."""
    structure = floor_structure(oracle.field, oracle.config.robot_radius)
    starts = sample_corridor_starts(oracle, structure, STRUCTURE_STARTS,
                                    np.random.default_rng(0))
    path = out / f"{floor}_structure.png"
    plot_floor_structure(grid, structure, starts, f"{floor}: corridor structure", path)
    return path, structure


def main(argv=None, description=None):
    """Parse, plot every floor of --starts (a map YAML path, or a name: maps/<name>.yaml of
    tamp_resources) -> exit status 0."""
    root = workspace()
    args = argument_parser(description).parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    for key, entries in yaml.safe_load(args.starts.read_text()).items():
        path = floor_map_path(key, resource("maps"))
        floor, grid = path.stem, load_map(path)
        oracle = RouteOracle(grid)
        for number, entry in enumerate(entries, 1):
            path, found = plot_start_goals(floor, grid, oracle, number, entry, args.out)
            print(f"{shown(path, root)}: {found} of {NUM_CLASSES} classes applicable")
        path, structure = plot_structure(floor, grid, oracle, args.out)
        print(f"{shown(path, root)}: {len(structure.junctions)} junction cells, "
              f"{len(structure.dead_ends)} dead-end cells")
    return 0
