"""Command line of scripts/fit_planner_settings: the static benchmark over the settings §5.3 leaves
open (robot speed, service durations), scored against the thesis's Tables 5-7 and 5-9."""
import argparse
import time
from pathlib import Path

import yaml
from tamp_resources import resource, workspace

from task_planner.tools import settings_fit as fit
from task_planner.tools import thesis_comparison as thesis
from task_planner.tools.bench_planner import make_config
from task_planner.tools.benchmark_report import _table
from task_planner.graph import load_graph
from task_planner.reward import load_priorities


GRAPHS = ("household", "office_ring", "office_loop", "office_crossroads", "office_longhall")


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--graphs", nargs="+", type=Path,
                        default=[resource("maps", f"{name}.graph.yaml") for name in GRAPHS],
                        help="topological graphs to run on (default: the household and the "
                             "office floors with a graph)")
    parser.add_argument("--priorities", default=resource("config", "priorities.yaml"), type=Path)
    parser.add_argument("--planner-config", default=resource("config", "task_planner.yaml"),
                        type=Path)
    parser.add_argument("--out", default=workspace() / "docs" / "planner" / "SETTINGS_FIT.md",
                        type=Path,
                        help="Markdown report (default: %(default)s)")
    parser.add_argument("--trials", type=int, default=100,
                        help="static sets per setting (default: %(default)s)")
    parser.add_argument("--seed", type=int, default=0, help="set generator seed (default: 0)")
    parser.add_argument("--command", default="scripts/fit_planner_settings",
                        help=argparse.SUPPRESS)
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    config = make_config(argparse.Namespace(
        planner_config=args.planner_config, static_trials=args.trials, opt_trials=0,
        scaling_trials=0, exact_trials=0, exact_limit_s=0.0, dynamic_trials=0, seed=args.seed))
    radius = float(yaml.safe_load(args.planner_config.read_text())["robot_radius_m"])
    graphs = {path.name.removesuffix(".graph.yaml"): load_graph(path, robot_radius=radius)
              for path in args.graphs}
    priorities = list(load_priorities(args.priorities).values())
    started = time.perf_counter()
    results = fit.sweep(graphs, priorities, config)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    figure = args.out.with_name(args.out.stem.lower() + ".png")
    fit.plot(results, figure)
    text = report(args, graphs, results, time.perf_counter() - started, figure.name)
    args.out.write_text(text)
    print(text)


def report(args, graphs, results, elapsed, figure):
    places = ", ".join(f"`{name}` {graph.size}" for name, graph in graphs.items())
    lines = ["# Planner settings against the thesis's Tables 5-7 and 5-9", "",
             "Written by `scripts/fit_planner_settings` (`task_planner.tools.settings_fit`) from "
             "one run:", "", f"    {args.command}", "",
             f"{args.trials} static sets of 10 instructions per setting (seed {args.seed}: the "
             f"same sets' priorities in every setting), on the graphs with places: {places}; "
             f"{elapsed:.0f} s in all. Ratios are mean reward over the exact optimum's mean "
             "reward; similarity is the Eq. 5-1 cost to the exact optimum's order; times are mean "
             "completion [s]; the gaps are root mean squares over the planners against the "
             "thesis's row (times: of the relative difference). The orders are Table 5-7's "
             "Ours > SF > PF > FCFS, Rand and Table 5-9's Ours < PF < SF < FCFS, Rand (FCFS and "
             "Rand are both random orders of a static set and are not compared with each other). "
             f"{', '.join(thesis.REWARD_ORDER)} are the thesis's names; \"Ours\" is one reading "
             "of Algorithm 4-2 per table.", "", f"![Ours vs SF]({figure})", ""]
    for reading in fit.readings():
        lines += [f"## Ours = {reading}", "",
                  _table(fit.summary_header(), fit.summary_rows(results, reading)), "",
                  "<details><summary>Every setting</summary>", "",
                  _table(fit.fit_header(), [fit.thesis_row()] + fit.fit_rows(results, reading)),
                  "", "</details>", ""]
    return "\n".join(lines)
