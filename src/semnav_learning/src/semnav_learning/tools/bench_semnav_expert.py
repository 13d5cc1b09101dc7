"""Expert demonstrations on every office floor driven with unicycle kinematics (expert.rehearse,
no simulator): how many reach the oracle's goal region without the robot centre coming closer
to a wall than the robot radius: scripts/bench_semnav_expert."""
import argparse
import math
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from floorplan.occupancy_map import load_map
from semantic_nav.instruction_classes import CLASS_IDS
from semnav_learning.expert import ExpertConfig, rehearse
from semnav_learning.floor_structure import floor_structure, sample_corridor_starts
from semnav_learning.route_oracle import RouteOracle
from tamp_resources import resource


@dataclass
class FloorBench:
    """The rehearsals of one floor."""

    ok: int = 0                     # reached the goal without touching a wall
    per_class: Counter = field(default_factory=Counter)   # rehearsals per applicable class
    steps: list = field(default_factory=list)             # commands per rehearsal
    failures: list = field(default_factory=list)  # (start, class, reached, min clearance [m])
    seconds: float = 0.0
    demo_ms: list = field(default_factory=list)   # wall time of each rehearsal [ms]

    @property
    def total(self):
        return sum(self.per_class.values())


def argument_parser(description=None):
    """The options of bench_semnav_expert."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--starts", type=int, default=20, help="starts per floor")
    parser.add_argument("--seed", type=int, default=0)
    return parser


def office_floors(maps_dir):
    """The office_* map YAML files of `maps_dir` (not their graphs), sorted."""
    return [path for path in sorted(Path(maps_dir).glob("office_*.yaml"))
            if not path.name.endswith(".graph.yaml")]


def bench_floor(path, starts, seed):
    """Rehearse every applicable class from `starts` sampled starts (DART noise, a random
    start displacement) on the floor of map YAML `path` -> FloorBench."""
    rng = np.random.default_rng(seed)
    oracle = RouteOracle(load_map(path))
    structure = floor_structure(oracle.field, oracle.config.robot_radius)
    poses = sample_corridor_starts(oracle, structure, starts, rng)
    bench = FloorBench()
    began = time.perf_counter()
    for start in poses:
        walk = oracle.walk(start)
        for label in CLASS_IDS:
            offset = (rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2),
                      math.radians(rng.uniform(-8, 8)))
            t0 = time.perf_counter()
            demo = rehearse(oracle, start, label, ExpertConfig(), rng, offset, walk)
            if demo is None:
                continue
            bench.demo_ms.append((time.perf_counter() - t0) * 1e3)
            bench.per_class[label] += 1
            bench.steps.append(len(demo.poses))
            if demo.reached and demo.min_clearance >= oracle.config.robot_radius:
                bench.ok += 1
            else:
                bench.failures.append((tuple(round(v, 2) for v in start), label, demo.reached,
                                       round(demo.min_clearance, 2)))
    bench.seconds = time.perf_counter() - began
    return bench


def report_lines(name, bench):
    """The lines of one floor: its success share, then one per failure."""
    lines = [f"{name}: {bench.ok}/{bench.total} = {100.0 * bench.ok / bench.total:.1f} % reach "
             f"the goal without touching a wall; {np.mean(bench.steps):.0f} commands per demo; "
             f"{bench.seconds:.1f} s; a demo p50 {np.percentile(bench.demo_ms, 50):.1f} ms, "
             f"p99 {np.percentile(bench.demo_ms, 99):.1f} ms; "
             f"per class {dict(sorted(bench.per_class.items()))}"]
    lines += [f"  failed: start {start} class {label} reached={reached} min clearance "
              f"{clearance} m" for start, label, reached, clearance in bench.failures]
    return lines


def main(argv=None, description=None):
    """Parse, rehearse on every office floor of tamp_resources' maps/, print -> exit status 0."""
    args = argument_parser(description).parse_args(argv)
    for path in office_floors(resource("maps")):
        for line in report_lines(path.stem, bench_floor(path, args.starts, args.seed)):
            print(line)
    return 0
