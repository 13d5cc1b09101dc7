"""Fleet allocator benchmark, ROS-free: every allocator of `fleet_registry` on seeded random
instruction sets over the household graph (Table 5-5 priorities, durations 1-10 s, 0.5 m/s).

  scripts/bench_fleet [--sets 20] [--count 10] [--counts 10,20,50,100,200] [--robots 2,3,5]
                      [--scaling-sets 3] [--arrival-sets 20] [--seed 0] [--markdown FILE]

- `exact`: on seeds `--seed` and `--seed` + 1, `--sets` sets of `--count` instructions launched
  together (all at 0) and `--sets` launched staggered (Poisson, mean gap 20 s), two robots on the
  charging place: each allocator's reward over the exact fleet optimum (`fleet_exact`, which knows
  every launch in advance), mean and worst, and the optimum's solve time; `--markdown` writes
  these ratios as a table;
- `scaling`: every count of `--counts` with every robot count of `--robots`: mean reward and the
  decision time per call (p50, p99) of each allocator;
- `arrivals`: 20 instructions launched as a Poisson stream (mean gap 20 s, as
  `scripts/bench_planner`'s dynamic part), one, two and three robots: mean reward per allocator.
"""
import argparse
import time

import numpy as np

from supervision.latency import summarise
from task_planner.tools.bench_executor import positive
from task_planner.tools.benchmark import BenchConfig, random_instructions
from task_planner.fleet import RobotStart, run_fleet
from task_planner.fleet_exact import fleet_exact_optimum
from task_planner.fleet_registry import FLEET_ALLOCATORS, make_allocator
from task_planner.fleet_waiting import online_ceiling
from task_planner.graph import load_graph
from task_planner.problem import Problem
from task_planner.reward import load_priorities
from tamp_resources import resource

START_NODE = 0            # the household's charging place
ROBOT_RADIUS_M = 0.25     # config/task_planner.yaml robot_radius_m
ARRIVAL_COUNT = 20
ARRIVAL_GAP_S = 20.0      # mean time between Poisson launches [s]
EXACT_MAX = 12            # fleet_exact_optimum's default limit on instructions
TOGETHER, STAGGERED = "together", "staggered"
LAUNCHES = (TOGETHER, STAGGERED)


def household():
    """(graph, priorities, instruction settings) of the benchmark."""
    graph = load_graph(resource("maps", "household.graph.yaml"), robot_radius=ROBOT_RADIUS_M)
    priorities = list(load_priorities(resource("config", "priorities.yaml")).values())
    return graph, priorities, BenchConfig()


def problem_set(graph, priorities, config, rng, count, launches=None):
    instructions = random_instructions(rng, count, priorities, graph.size, config, launches)
    return Problem(graph, instructions, config.speed_mps, START_NODE)


def run_allocators(problem, robots):
    """{allocator name: (reward, decision times [s])} on one problem."""
    starts = [RobotStart(START_NODE)] * robots
    results = {}
    for name in FLEET_ALLOCATORS:
        run = run_fleet(problem, starts, make_allocator(name))
        results[name] = (run.reward(problem), run.decision_calls)
    return results


class Progress:
    """One line per finished item with the time elapsed and an ETA."""

    def __init__(self, part, total, out):
        self.part, self.total, self.out, self.done = part, total, out, 0
        self.started = time.perf_counter()

    def step(self, what):
        self.done += 1
        elapsed = time.perf_counter() - self.started
        self.out(f"  [{self.part}] {self.done}/{self.total} {what}; {elapsed:.0f} s elapsed, "
                 f"ETA {elapsed / self.done * (self.total - self.done):.0f} s")


def poisson_launches(rng, count):
    """Launch times of `count` instructions: the first at 0, then exponential gaps."""
    gaps = rng.exponential(ARRIVAL_GAP_S, count)
    return np.concatenate([[0.0], np.cumsum(gaps[1:])])


def exact_part(graph, priorities, config, sets, count, seeds, out=print):
    """Ratios to the exact optimum with two robots, per seed of `seeds` and launch mode;
    returns {(seed, mode): {name: [ratio per set]}}."""
    out(f"exact: {sets} sets of {count} instructions per seed and launch mode (together: all "
        f"at 0; staggered: Poisson, mean gap {ARRIVAL_GAP_S:.0f} s), 2 robots on node "
        f"{START_NODE}")
    table, solve_s = {}, []
    progress = Progress("exact", sets * len(seeds) * len(LAUNCHES), out)
    for seed in seeds:
        rng = np.random.default_rng(seed)
        for mode in LAUNCHES:
            ratios = table[seed, mode] = {name: [] for name in FLEET_ALLOCATORS}
            for _ in range(sets):
                launches = poisson_launches(rng, count) if mode == STAGGERED else None
                problem = problem_set(graph, priorities, config, rng, count, launches)
                started = time.perf_counter()
                _, best = fleet_exact_optimum(problem, [RobotStart(START_NODE)] * 2)
                solve_s.append(time.perf_counter() - started)
                for name, (reward, _) in run_allocators(problem, 2).items():
                    ratios[name].append(reward / best)
                progress.step(f"seed {seed}, {mode}: optimum {best:.3f} in {solve_s[-1]:.2f} s")
    for line in ratio_table(table):
        out("  " + line)
    ceiling = online_ceiling(problem.travel_s, 2, [(q.gamma, q.beta) for q in priorities],
                             range(config.duration_min_s, config.duration_max_s + 1))
    out(f"  online ceiling (fleet_waiting.online_ceiling; launches one at a time, robots idle): "
        f"{ceiling:.3f} of an optimum with a robot waiting at every destination")
    out(f"  exact optimum solve time: p50 {np.median(solve_s):.2f} s, max {max(solve_s):.2f} s")
    return table


def ratio_table(table):
    """Markdown rows: per allocator, mean and worst ratio of every (seed, launch mode)."""
    keys = list(table)
    lines = ["| allocator | " + " | ".join(f"seed {seed}, {mode}: mean / worst"
                                            for seed, mode in keys) + " |",
             "|---|" + "---|" * len(keys)]
    for name in FLEET_ALLOCATORS:
        lines.append(f"| `{name}` | " + " | ".join(
            f"{np.mean(table[key][name]):.3f} / {np.min(table[key][name]):.3f}"
            for key in keys) + " |")
    return lines


def scaling_part(graph, priorities, config, counts, robots, sets, rng, out=print):
    """Mean reward and decision times per (count, robots, allocator)."""
    out(f"scaling: {sets} static sets per count and robot count")
    table = {}
    progress = Progress("scaling", len(counts) * len(robots) * sets, out)
    for count in counts:
        for k in robots:
            rewards, calls = {n: [] for n in FLEET_ALLOCATORS}, {n: [] for n in FLEET_ALLOCATORS}
            for _ in range(sets):
                problem = problem_set(graph, priorities, config, rng, count)
                for name, (reward, decisions) in run_allocators(problem, k).items():
                    rewards[name].append(reward)
                    calls[name] += decisions
                progress.step(f"{count} instructions, {k} robots")
            table[count, k] = {n: (float(np.mean(rewards[n])), calls[n]) for n in rewards}
    out("  | instructions | robots | " + " | ".join(
        f"{n}: reward, decision p50 / p99 [ms]" for n in FLEET_ALLOCATORS) + " |")
    for (count, k), row in table.items():
        cells = [f"{reward:.2f}, {ms.p50:.2f} / {ms.p99:.2f}"
                 for reward, ms in ((r, summarise(1e3 * c for c in calls))
                                    for r, calls in row.values())]
        out(f"  | {count} | {k} | " + " | ".join(cells) + " |")
    return table


def arrivals_part(graph, priorities, config, sets, rng, out=print):
    """Mean reward per (robots, allocator) on Poisson arrivals."""
    out(f"arrivals: {sets} sets of {ARRIVAL_COUNT} instructions, Poisson launches every "
        f"{ARRIVAL_GAP_S:.0f} s on average")
    rewards = {(k, n): [] for k in (1, 2, 3) for n in FLEET_ALLOCATORS}
    progress = Progress("arrivals", sets, out)
    for _ in range(sets):
        problem = problem_set(graph, priorities, config, rng, ARRIVAL_COUNT,
                              poisson_launches(rng, ARRIVAL_COUNT))
        for k in (1, 2, 3):
            for name, (reward, _) in run_allocators(problem, k).items():
                rewards[k, name].append(reward)
        progress.step("1, 2 and 3 robots")
    for k in (1, 2, 3):
        out(f"  {k} robot{'s' if k > 1 else ''}: " + ", ".join(
            f"{n} {np.mean(rewards[k, n]):.3f}" for n in FLEET_ALLOCATORS))
    return rewards


def int_list(text):
    try:
        values = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        values = []
    if not values or min(values) < 1:
        raise argparse.ArgumentTypeError(f"must be positive integers separated by commas; got "
                                         f"{text!r}")
    return values


def parser():
    p = argparse.ArgumentParser(prog="bench_fleet", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--sets", type=positive, default=20,
                   help="static sets compared with the exact optimum (default: %(default)s)")
    p.add_argument("--count", type=positive, default=10,
                   help="instructions per set compared with the optimum (default: %(default)s)")
    p.add_argument("--counts", type=int_list, default=[10, 20, 50, 100, 200],
                   help="instruction counts of the scaling part (default: 10,20,50,100,200)")
    p.add_argument("--robots", type=int_list, default=[2, 3, 5],
                   help="robot counts of the scaling part (default: 2,3,5)")
    p.add_argument("--scaling-sets", type=positive, default=3,
                   help="sets per count and robot count (default: %(default)s)")
    p.add_argument("--arrival-sets", type=positive, default=20,
                   help="Poisson arrival sets (default: %(default)s)")
    p.add_argument("--seed", type=int, default=0,
                   help="random seed; the exact part also runs the next one (default: "
                        "%(default)s)")
    p.add_argument("--markdown", metavar="FILE",
                   help="write the exact part's ratios to FILE as a Markdown table")
    return p


def main(argv=None, out=print):
    args = parser().parse_args(argv)
    if args.count > EXACT_MAX:
        parser().error(f"--count: the exact optimum takes sets of up to {EXACT_MAX} "
                       f"instructions; got {args.count}")
    graph, priorities, config = household()
    table = exact_part(graph, priorities, config, args.sets, args.count,
                       (args.seed, args.seed + 1), out)
    if args.markdown:
        write_markdown(args.markdown, table, args, out)
    rng = np.random.default_rng(args.seed)
    scaling_part(graph, priorities, config, args.counts, args.robots, args.scaling_sets, rng, out)
    arrivals_part(graph, priorities, config, args.arrival_sets, rng, out)
    return 0


def write_markdown(path, table, args, out=print):
    """The exact part's ratios as a Markdown page at `path`."""
    text = "\n".join([
        "# Fleet allocators against the exact k-robot optimum",
        "",
        f"`scripts/bench_fleet --sets {args.sets} --count {args.count} --seed {args.seed}` "
        f"(household graph, two robots on the charging place; each allocator's reward over "
        f"the exact optimum of `fleet_exact`, which knows every launch in advance; "
        f"{args.sets} sets of {args.count} instructions per seed, launched together at 0 or "
        f"staggered as a Poisson stream with a mean gap of {ARRIVAL_GAP_S:.0f} s):",
        "", *ratio_table(table), ""])
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    out(f"wrote {path}")
