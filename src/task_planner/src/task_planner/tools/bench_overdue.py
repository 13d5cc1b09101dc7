"""How long people wait under each order of overdue instructions (deciding.overdue_first).

The executor (rollout planner, `serve_within_s` 120 s as the household launch) drives the
household graph in the in-process navigation model (executor_sim) while people's requests arrive
as a Poisson stream: random place, priority (Table 5-5's four people's levels) and robot
function (its duration from config/robot_functions.yaml). Three loads: steady (one request every
90 s for 30 min), a burst (one every 40 s for 400 s, as a day's first minutes when the robot
still meets everyone) and an overload (one every 60 s for 30 min). Per order of
`task_planner.executor.OVERDUE_ORDERS` and load: the median and the worst wait from launch to
the start of service (means over the seeds, and the largest), and the reward earned.
"""
import argparse
import random
import statistics
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from tamp_resources import resource

from task_planner.executor import OVERDUE_ORDERS, Executor, ExecutorConfig
from task_planner.executor_sim import NavigationModel, run_executor
from task_planner.graph import load_graph
from task_planner.instruction import HUMAN, Instruction
from task_planner.people_belief import PeopleAtPlaces
from task_planner.planner_registry import make_planner
from task_planner.reward import load_priorities
from task_planner.robot_functions import load_robot_functions
from task_planner.task_buffer import BufferConfig, TaskBuffer

PEOPLE_LEVELS = ("physical", "negative", "neutral", "positive")   # config/priorities.yaml
OWN_FUNCTIONS = ("charge", "introduce")   # the robot's own, never a person's request
SERVE_WITHIN_S = 120.0                    # ros_executor's ~serve_within
SPEED_MPS = 0.5                           # config/task_planner.yaml speed_mps
LOADS = {   # name: (mean gap between requests [s], requests arrive until [s])
    "steady": (90.0, 1800.0),
    "burst": (40.0, 400.0),
    "overload": (60.0, 1800.0),
}


@dataclass(frozen=True)
class Waits:
    median_s: float    # median wait from launch to service start [s]
    worst_s: float     # the longest wait [s]
    reward: float      # Eq. 4-2 reward earned
    served: int
    count: int


def poisson_requests(seed, mean_gap_s, until_s, graph, priorities, functions):
    """People's requests launched as a Poisson stream until `until_s` [s]."""
    rng = random.Random(seed)
    levels = [priorities[name] for name in PEOPLE_LEVELS]
    codes = sorted(c for c, f in functions.items() if f.name not in OWN_FUNCTIONS)
    requests, t = [], 0.0
    while (t := t + rng.expovariate(1.0 / mean_gap_s)) <= until_s:
        level, code = rng.choice(levels), rng.choice(codes)
        requests.append(Instruction(
            id=len(requests) + 1, gamma=level.gamma, beta=level.beta,
            destination=rng.randrange(graph.size), start_time=t,
            duration=int(functions[code].duration_s), function=code, type=HUMAN))
    return requests


def waits(requests, order, graph, functions):
    """Run the executor on `requests` with `order` of the overdue ones; its Waits."""
    with tempfile.TemporaryDirectory() as folder:
        buffer = TaskBuffer(Path(folder) / "journal.sqlite", BufferConfig(node_count=graph.size))
        executor = Executor(buffer, graph, make_planner("rollout"), PeopleAtPlaces(), functions,
                            ExecutorConfig(speed_mps=SPEED_MPS, serve_within_s=SERVE_WITHIN_S,
                                           overdue_order=order))
        trace = run_executor(executor, [(r.start_time, r) for r in requests],
                             NavigationModel(graph, SPEED_MPS))
        reward = sum(r.reward_earned for r in buffer.records())
    started = {}
    for t, instruction_id, _ in trace.executed:
        started.setdefault(instruction_id, t)
    waited = [started[r.id] - r.start_time for r in requests if r.id in started]
    if not waited:
        return Waits(float("nan"), float("nan"), reward, 0, len(requests))
    return Waits(statistics.median(waited), max(waited), reward, len(started), len(requests))


def markdown(rows, seeds, seconds):
    lines = ["| load | order | median wait [s] | worst wait, mean [s] | worst wait, largest [s] "
             "| reward | served |", "|---|---|---|---|---|---|---|"]
    for (load, order), runs in rows.items():
        lines.append(
            f"| {load} | {order} | {statistics.mean(w.median_s for w in runs):.0f} | "
            f"{statistics.mean(w.worst_s for w in runs):.0f} | "
            f"{max(w.worst_s for w in runs):.0f} | {statistics.mean(w.reward for w in runs):.2f} "
            f"| {sum(w.served for w in runs)}/{sum(w.count for w in runs)} |")
    lines.append(f"\nSeeds {seeds[0]}-{seeds[-1]}; {seconds:.0f} s.")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10, help="request streams per load")
    parser.add_argument("--first-seed", type=int, default=0)
    args = parser.parse_args(argv)
    if args.seeds < 1:
        parser.error("--seeds must be at least 1")
    graph = load_graph(resource("maps", "household.graph.yaml"))
    priorities = load_priorities(resource("config", "priorities.yaml"))
    functions = load_robot_functions(resource("config", "robot_functions.yaml"))
    seeds = list(range(args.first_seed, args.first_seed + args.seeds))
    rows, began = {}, time.monotonic()
    total, done = len(LOADS) * len(seeds) * len(OVERDUE_ORDERS), 0
    for load, (gap_s, until_s) in LOADS.items():
        for seed in seeds:
            requests = poisson_requests(seed, gap_s, until_s, graph, priorities, functions)
            for order in OVERDUE_ORDERS:
                rows.setdefault((load, order), []).append(waits(requests, order, graph,
                                                                functions))
                done += 1
            elapsed = time.monotonic() - began
            print(f"[bench_overdue] {done}/{total} runs, {elapsed:.0f} s, "
                  f"ETA {elapsed / done * (total - done):.0f} s", flush=True)
    print(markdown(rows, seeds, time.monotonic() - began))
    return 0
