"""Command line of scripts/bench_planner: run the benchmark, write JSON, Markdown and PNGs."""
import argparse
import json
import os
import platform
import time
from pathlib import Path

import yaml
from tamp_resources import resource, workspace

from task_planner.tools import benchmark as bench
from task_planner.tools import benchmark_report as report
from task_planner.tools import thesis_comparison as thesis
from task_planner.graph import load_graph
from task_planner.planner_registry import label
from task_planner.reward import load_priorities
from task_planner.rollout_planner import RolloutConfig


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--graph", default=resource("maps", "household.graph.yaml"), type=Path)
    parser.add_argument("--priorities", default=resource("config", "priorities.yaml"), type=Path)
    parser.add_argument("--planner-config", default=resource("config", "task_planner.yaml"),
                        type=Path)
    parser.add_argument("--out-dir", default=workspace() / "docs" / "planner", type=Path)
    parser.add_argument("--json", type=Path, help="write all trials in the re-scoring schema")
    defaults = bench.BenchConfig()
    for name in ("static_trials", "opt_trials", "scaling_trials", "exact_trials",
                 "dynamic_trials", "seed"):
        parser.add_argument("--" + name.replace("_", "-"), type=int,
                            default=getattr(defaults, name))
    parser.add_argument("--exact-limit-s", type=float, default=defaults.exact_limit_s)
    parser.add_argument("--command", default="scripts/bench_planner", help=argparse.SUPPRESS)
    return parser.parse_args(argv)


def make_config(args):
    planner = yaml.safe_load(args.planner_config.read_text())
    return bench.BenchConfig(
        static_trials=args.static_trials, opt_trials=args.opt_trials,
        scaling_trials=args.scaling_trials, exact_trials=args.exact_trials,
        exact_limit_s=args.exact_limit_s, dynamic_trials=args.dynamic_trials, seed=args.seed,
        speed_mps=float(planner["speed_mps"]), step_s=float(planner["step_s"]),
        opt_max_instructions=int(planner["opt_max_instructions"]),
        exact_max_instructions=int(planner["exact_max_instructions"]),
        rollout=RolloutConfig(int(planner["rollout_candidates"]), int(planner["rollout_horizon"]),
                              float(planner["rollout_tail_weight"])))


def main(argv=None):
    args = parse_args(argv)
    config = make_config(args)
    radius = float(yaml.safe_load(args.planner_config.read_text())["robot_radius_m"])
    graph = load_graph(args.graph, robot_radius=radius)
    priorities = list(load_priorities(args.priorities).values())
    args.out_dir.mkdir(parents=True, exist_ok=True)
    clock, load_before = time.perf_counter(), os.getloadavg()[0]
    parts = {}
    for name, run in (("static", lambda: bench.run_static(graph, priorities, config)),
                      ("named", lambda: bench.run_named_case(graph, config)),
                      ("scaling", lambda: bench.run_scaling(graph, priorities, config)),
                      ("exact", lambda: bench.run_exact_scaling(graph, priorities, config)),
                      ("dynamic", lambda: bench.run_dynamic(graph, priorities, config))):
        started = time.perf_counter()
        parts[name] = run()
        print(f"[bench_planner] {name}: {time.perf_counter() - started:.1f} s", flush=True)
    elapsed = time.perf_counter() - clock
    if args.json:
        write_json(args.json, graph, config, parts)
    load = (load_before, os.getloadavg()[0])
    text = results_markdown(args, config, graph, parts, elapsed, load)
    (args.out_dir / "RESULTS.md").write_text(text)
    write_plots(args.out_dir, parts)
    print(text)


def write_json(path, graph, config, parts):
    document = bench.json_document(graph, config, parts["static"][0], parts["dynamic"][0],
                                   parts["named"][1])
    Path(path).write_text(json.dumps(document))


def write_plots(out_dir, parts):
    problem, _, schedules = parts["named"]
    report.plot_named_case(problem, schedules, out_dir / "fig_5_6_table_5_6_reward.png")
    scaling = parts["scaling"]
    report.plot_scaling(scaling, "total_s", "total processing time [s]",
                        "Processing time (cf. Fig. 5-8)", out_dir / "fig_5_8_processing_time.png")
    report.plot_scaling(scaling, "time_ratio", "time ratio (Eq. 5-2)",
                        "Time ratio (cf. Fig. 5-9)", out_dir / "fig_5_9_time_ratio.png")
    report.plot_scaling(scaling, "latency_mean_ms", "mean decision latency per call [ms]",
                        "Decision latency of the online planners", out_dir / "decision_latency.png",
                        names=report.LATENCY_NAMES)
    report.plot_exact(parts["exact"], out_dir / "exact_runtime.png")


def results_markdown(args, config, graph, parts, elapsed, load):
    static_rows = parts["static"][1]
    problem, named_record, schedules = parts["named"]
    seeds = [label("seed"), label("seed_step")]
    guards = ", ".join(f"{name} {sum(row[name]['guard_activations'] for row in static_rows)}"
                       for name in seeds)
    shape = thesis.static_shape(static_rows, label("exact_offline"))
    return "\n".join([
        "# Task planner benchmark (thesis 000 §5.3)", "",
        "Written by `scripts/bench_planner` from one run:", "", f"    {args.command}", "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores "
        f"shared with other jobs (1-min load average {load[0]:.1f} at the start, {load[1]:.1f} at "
        f"the end; decision times are wall-clock), Python {platform.python_version()}; total run "
        f"time {elapsed:.0f} s. Graph `{args.graph.name}`: {graph.size} places, "
        f"{len(graph.edges())} edges (A* lengths); speed {config.speed_mps} m/s; robot starts on "
        f"`{graph.names[config.start_node]}`; durations uniform {config.duration_min_s}-"
        f"{config.duration_max_s} s; priorities of Table 5-5 drawn uniformly; seed {config.seed}.",
        "", f"Planners (`task_planner.planner_registry`): {report.planner_legend()}. "
        "\"w/ decision\" adds each planner's measured decision time (the seed's \"Opt w/m\").", "",
        f"## Static sets of {config.static_count} instructions (Tables 5-7, 5-9)", "",
        f"{config.static_trials} random sets; Opt ran on the first {config.opt_trials} only "
        "(its row averages those). Similarity cost (Eq. 5-1) is to the exact optimum's order.", "",
        report.static_table(static_rows), "", report.opt_check(static_rows), "",
        f"Loop guard activations in these {config.static_trials} trials: {guards}.", "",
        "### Against the thesis's Tables 5-7 and 5-9", "",
        "Reward as the thesis gives it: the mean reward over the optimum's mean reward (Opt's in "
        "the thesis, the exact optimum's here); similarity cost as above. Both readings of "
        "Algorithm 4-2 stand for the thesis's \"Ours\" "
        "(`task_planner.tools.thesis_comparison`):", "",
        report.thesis_table(thesis.comparison_rows(shape, seeds)), "",
        *[f"- {thesis.verdict(shape, name)}" for name in seeds], "",
        "## The seed's example set (Table 5-6 / Table 5-8)", "",
        "gamma and beta from Table 5-6; the thesis does not give nodes or durations, so they are "
        "drawn with a fixed seed (56):", "", report.instructions_table(problem), "",
        report.named_case_table(problem, named_record, schedules), "",
        "![Table 5-6 reward](fig_5_6_table_5_6_reward.png)", "",
        "## Scaling (Fig. 5-8, 5-9)", "",
        f"{config.scaling_trials} random sets per size. Total processing time [s] "
        "(completion of the last instruction, decision time included):", "",
        report.scaling_table(parts["scaling"], "total_s", "{:.0f}"), "",
        "Time ratio (Eq. 5-2: task time / (task + decision + navigation time)):", "",
        report.scaling_table(parts["scaling"], "time_ratio", "{:.3f}"), "",
        "Decision latency per planner call of the online planners (wall clock: mean, median of "
        "the per-set medians, worst per-set p99, max; and the worst per-set p99 of the calls' "
        "thread CPU time, which leaves out time spent waiting for a shared core):", "",
        report.latency_table(parts["scaling"]), "",
        "![processing time](fig_5_8_processing_time.png) ![time ratio](fig_5_9_time_ratio.png)",
        "![latency](decision_latency.png)", "",
        "## Exact optimiser runtime", "",
        f"{config.exact_trials} random sets per size, time limit {config.exact_limit_s} s per set "
        "(stops at the first size not solved within the limit every time):", "",
        report.exact_table(parts["exact"]), "", "![exact runtime](exact_runtime.png)", "",
        f"## Dynamic arrivals ({config.dynamic_count} instructions, Poisson launches, mean gap "
        f"{config.dynamic_mean_gap_s} s)", "",
        f"{config.dynamic_trials} trials; reward counted from each launch; planners see an "
        "instruction only once launched.", "", report.dynamic_table(parts["dynamic"][1]), ""])


if __name__ == "__main__":
    main()
