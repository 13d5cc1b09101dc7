"""Executor decision latency under a flood: N instructions in one second, then serve some.

Usage: scripts/bench_executor [--count 1000] [--burst 50] [--planner NAME] (names: --help)
The flood arrives in bursts (one per 20 Hz executor tick) while the robot drives the household
graph; each burst is journalled (SQLite, synchronous=FULL by default) and re-decided. A node step
that serves or finishes an instruction includes its durable write-back (one disk sync). Prints
the wall time per burst (journal + decision), per node step (fetch, decode, decide, write back)
and per decision alone (fetch, decode, decide: the executor's own timing) as p50, p95, p99 and
max, and checks the journal holds every instruction.
"""
import argparse
import os
import random
import tempfile
import time
from pathlib import Path

import yaml
from supervision.latency import summarise
from tamp_resources import resource

from task_planner.executor import Executor, ExecutorConfig
from task_planner.executor_sim import NavigationModel, _start_drive
from task_planner.graph import load_graph
from task_planner.instruction import Instruction
from task_planner.people_belief import PeopleAtPlaces
from task_planner.planner_registry import EXECUTOR, make_planner, planner_names
from task_planner.reward import load_priorities
from task_planner.robot_functions import load_robot_functions
from task_planner.task_buffer import BufferConfig, TaskBuffer


def flood(count, graph, priorities, rng):
    """`count` random instructions launched evenly within the first second."""
    rows = list(priorities.values())
    return [Instruction(id=k, gamma=(p := rng.choice(rows)).gamma, beta=p.beta,
                        destination=rng.randrange(graph.size), start_time=k / count,
                        duration=rng.choice((15, 20, 30)), function=rng.randint(1, 7))
            for k in range(1, count + 1)]


def positive(text):
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer; got {text!r}")
    return int(text)


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="bench_executor", description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=positive, default=1000)
    parser.add_argument("--burst", type=positive, default=50)
    parser.add_argument("--planner", choices=planner_names(EXECUTOR), default="seed")
    parser.add_argument("--decisions", type=positive, default=30, help="node decisions timed")
    parser.add_argument("--synchronous", default="FULL",
                        choices=("OFF", "NORMAL", "FULL", "EXTRA"),
                        help="journal PRAGMA synchronous (OFF isolates the decision from disk)")
    return parser.parse_args(argv)


def run_flood(args, settings, graph, folder):
    """(burst times, node-step times [s], executor, instructions journalled) of one flood."""
    instructions = flood(args.count, graph, load_priorities(resource("config", "priorities.yaml")),
                         random.Random(0))
    functions = load_robot_functions(resource("config", "robot_functions.yaml"))
    navigation = NavigationModel(graph, settings["speed_mps"])
    journal = Path(folder) / "buffer.sqlite"
    buffer = TaskBuffer(journal, BufferConfig(args.synchronous, graph.size))
    planner = make_planner(args.planner, settings, use=EXECUTOR)
    executor = Executor(buffer, graph, planner, PeopleAtPlaces(), functions,
                        ExecutorConfig(speed_mps=settings["speed_mps"]))
    burst_s = []
    for first in range(0, args.count, args.burst):
        started = time.perf_counter()
        executor.receive(instructions[first:first + args.burst], now=first / args.count)
        burst_s.append(time.perf_counter() - started)
    decision_s, clock = [], 1.0
    for _ in range(args.decisions):  # drive node to node (and serve) as the executor decides
        if executor.mode == "moving":
            drive = _start_drive(navigation, None, executor.node, executor.goal, clock)
            clock = drive.eta
            started = time.perf_counter()
            executor.arrived(clock)
        else:
            clock = executor.state.executing[1] if executor.state.executing else clock
            started = time.perf_counter()
            executor.tick(clock)
        decision_s.append(time.perf_counter() - started)
    return burst_s, decision_s, executor, len(TaskBuffer(journal).records())


def latency_line(what, samples_s):
    """`  what: p50 .. ms, p95 .. ms, p99 .. ms, max .. ms` of wall times [s]."""
    if not samples_s:
        return f"  {what}: no samples"
    return f"  {what}: {summarise(1e3 * s for s in samples_s).describe()}"


def main(argv=None):
    args = parse_args(argv)
    settings = yaml.safe_load(resource("config", "task_planner.yaml").read_text())
    graph = load_graph(resource("maps", "household.graph.yaml"), settings["robot_radius_m"])
    with tempfile.TemporaryDirectory() as folder:
        burst_s, decision_s, executor, journalled = run_flood(args, settings, graph, folder)
    print(f"planner {args.planner}: {args.count} instructions in bursts of {args.burst}; "
          f"journalled {journalled}/{args.count} (synchronous={args.synchronous}); "
          f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    for what, samples in ((f"per burst (journal + re-decision), {len(burst_s)}", burst_s),
                          (f"per node step with ~{args.count} open (decide + write back), "
                           f"{len(decision_s)}", decision_s),
                          (f"per decision (fetch, decode, decide), {len(executor.decision_s)}",
                           executor.decision_s),
                          ("  the same, thread CPU time", executor.decision_cpu_s)):
        print(latency_line(what, samples))
    return 0 if journalled == args.count else 1
