"""Write the report of a scenario run (REPORT.md, rewards.png, trajectory.png) from its record
(the scenario node's JSON) and the executor's journal; prints the counts and reward figures."""
import argparse
from pathlib import Path

import yaml
from tamp_resources import resource, workspace
from task_planner.graph import load_graph

from tamp_bringup.bag_record import replay_command
from tamp_bringup.scenario_report import write_report


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="scenario_report", description=__doc__)
    parser.add_argument("record", type=Path, help="scenario record JSON")
    parser.add_argument("journal", type=Path, nargs="+",
                        help="executor task buffer journal (SQLite); a fleet's: every robot's")
    parser.add_argument("--out-dir", type=Path, default=workspace() / "docs" / "demo")
    parser.add_argument("--humans", type=Path, default=None,
                        help="the run's human database (SQLite): its history rows by source")
    parser.add_argument("--bag", type=Path, default=None,
                        help="the run's rosbag: the report says how to replay it in rviz")
    parser.add_argument("--graph", type=Path, default=resource("maps", "household.graph.yaml"))
    parser.add_argument("--map", type=Path, default=resource("maps", "household.yaml"))
    parser.add_argument("--settings", type=Path, default=resource("config", "task_planner.yaml"))
    parser.add_argument("--exact-limit-s", type=float, default=60.0,
                        help="time limit of the exact optimum [s]")
    args = parser.parse_args(argv)
    for name in ("record", "journal", "humans", "bag", "graph", "map", "settings"):
        for path in (getattr(args, name) if name == "journal" else [getattr(args, name)]):
            if path is not None and not path.is_file():
                parser.error(f"{name.replace('_', '-')}: no such file: {path}")
    if not args.exact_limit_s > 0:
        parser.error(f"--exact-limit-s must be positive; got {args.exact_limit_s}")
    return args


def summary_lines(result, out_dir):
    """What the command prints of write_report's summary."""
    lines = [f"requests {result['requests']}: served {result['served']}, failed "
             f"{result['failed']}; instructions {result['instructions']} {result['states']}",
             f"reward of the run {result['reward']:.3f}; model on the same arrivals: "
             + ", ".join(f"{name} {value:.3f}" for name, value in result["model"].items())]
    lines += [f"order: {problem}" for problem in result["order_problems"]]
    belief = result["belief"]
    if belief:
        lines.append(f"belief accuracy: mean {sum(belief.values()) / len(belief):.2f} ("
                     + ", ".join(f"{name} {value:.2f}" for name, value in belief.items())
                     + f"); searches {result['searches']}")
    if result["sources"]:
        lines.append("human_db history rows by source: " + ", ".join(
            f"{source} {count}" for source, count in result["sources"].items()))
    lines.append(f"report: {Path(out_dir) / 'REPORT.md'}")
    if result.get("replay"):
        lines.append(f"replay in rviz: {result['replay']}")
    return lines


def main(argv=None):
    args = parse_args(argv)
    settings = yaml.safe_load(args.settings.read_text())
    graph = load_graph(args.graph, float(settings["robot_radius_m"]))
    replay = replay_command(args.bag.resolve()) if args.bag is not None else None
    result = write_report(args.record, args.journal, graph, settings, args.map, args.graph,
                          args.out_dir, args.exact_limit_s, args.humans, replay)
    for line in summary_lines(result, args.out_dir):
        print(line)
    return 0
