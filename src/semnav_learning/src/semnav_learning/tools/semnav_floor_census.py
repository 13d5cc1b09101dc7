"""Command line of scripts/semnav_floor_census: per floor, the sampled corridor starts each
instruction class applies from (evaluation.class_census) and, for the corner turns, how many of
them turn where the same side's turn at the end does."""
import argparse

import numpy as np

from floorplan.occupancy_map import load_map
from semantic_nav.instruction_classes import CLASS_IDS, END_TURN
from semnav_learning.demonstrations import floor_map_path
from semnav_learning.evaluation import class_census
from semnav_learning.floor_structure import floor_structure, sample_corridor_starts
from semnav_learning.route_oracle import RouteOracle
from tamp_resources import resource


def argument_parser(description=None):
    """The options of semnav_floor_census."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("floors", nargs="+", help="names under maps/ or map YAML paths")
    parser.add_argument("--candidates", type=int, default=120, help="starts sampled per floor")
    parser.add_argument("--seed", type=int, default=0)
    return parser


def row(name, census):
    """One line: applicable starts per class, "/at the end" for the corner turns."""
    cells = (f"{applicable}/{at_end}" if label in END_TURN else str(applicable)
             for label, (applicable, at_end) in census.items())
    return name.ljust(20) + "".join(f"{cell:>9}" for cell in cells)


def header():
    """The two heading lines of the census table."""
    return ["floor".ljust(20) + "".join(f"{label:>9}" for label in CLASS_IDS),
            "(applicable starts / of them at the corridor's end)"]


def floor_census(path, candidates, rng):
    """class_census of `candidates` corridor starts sampled on the floor of map YAML `path`."""
    oracle = RouteOracle(load_map(path))
    structure = floor_structure(oracle.field, oracle.config.robot_radius)
    return class_census(oracle, sample_corridor_starts(oracle, structure, candidates, rng))


def main(argv=None, description=None):
    """Parse, print one row per floor (and the total of several) -> exit status 0; floor
    names are maps/<name>.yaml of tamp_resources."""
    args = argument_parser(description).parse_args(argv)
    rng = np.random.default_rng(args.seed)      # one generator over the floors in turn
    for line in header():
        print(line)
    totals = {label: np.zeros(2, int) for label in CLASS_IDS}
    for name in args.floors:
        path = floor_map_path(name, resource("maps"))
        census = floor_census(path, args.candidates, rng)
        for label, counts in census.items():
            totals[label] += counts
        print(row(path.stem, census), flush=True)
    if len(args.floors) > 1:
        print(row("total", totals))
    return 0
