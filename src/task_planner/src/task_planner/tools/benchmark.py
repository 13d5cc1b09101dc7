"""Planner benchmark of thesis 000 §5.3 (Tables 5-7 ... 5-9, Fig. 5-6 ... 5-9), ROS-free.

Runs the seed's planner, its baselines, the exhaustive Opt, the exact optimiser and our rollout
planner on seeded random instruction sets over a topological graph, and returns plain dicts that
serialise to the JSON schema of the issue (see `trial_record`). Each part runs the planners that
`planner_registry` lists for it (BENCH_*), in registration order.
"""
import time
from dataclasses import dataclass, field

import numpy as np

from task_planner.exact import SolverTimeout, warm_exact_optimum
from task_planner.instruction import Instruction
from task_planner.metrics import completion_time, navigation_time, similarity_cost, time_ratio
from task_planner.planner_registry import (BENCH_DYNAMIC, BENCH_SCALING, BENCH_STATIC,
                                           BENCH_STATIC_FEW, PlannerSettings, label,
                                           make_planners)
from task_planner.problem import Problem, schedule_reward
from task_planner.rollout_planner import RolloutConfig
from task_planner.simulate import run_planner

# Table 5-6: the seed's example set (gamma, beta); its nodes and durations are not given
TABLE_5_6 = [(3, .94), (8, .98), (1, .90), (1, .90), (2, .92), (3, .96), (1, .90), (5, .96),
             (2, .92), (8, .98)]


@dataclass
class BenchConfig:
    """What the benchmark runs; times in seconds."""

    static_trials: int = 200          # random sets of `static_count` instructions
    static_count: int = 10
    opt_trials: int = 10              # of those, how many also run the exhaustive Opt
    scaling_counts: tuple = (10, 20, 50, 100, 200)
    scaling_trials: int = 10
    exact_counts: tuple = (8, 10, 12, 15, 20, 25, 30, 35, 40)
    exact_trials: int = 3
    exact_limit_s: float = 10.0       # the exact optimiser's time budget per set [s]
    dynamic_trials: int = 40
    dynamic_count: int = 20
    dynamic_mean_gap_s: float = 20.0  # mean time between Poisson launches [s]
    duration_min_s: int = 1           # instruction durations are uniform integers [s]
    duration_max_s: int = 10
    speed_mps: float = 0.5            # navigation speed [m/s]
    step_s: float = 1.0               # ripple planner time step [s]
    start_node: int = 0               # the robot starts here (charging place on the household map)
    opt_max_instructions: int = 10
    exact_max_instructions: int = 40
    rollout: RolloutConfig = field(default_factory=RolloutConfig)  # improved planner settings
    seed: int = 0

    def planner_settings(self):
        """The settings the registry's planner factories read."""
        return PlannerSettings(step_s=self.step_s, opt_max_instructions=self.opt_max_instructions,
                               exact_max_instructions=self.exact_max_instructions,
                               rollout=self.rollout)


def random_instructions(rng, count, priorities, node_count, config, launches=None):
    """`count` instructions with a uniformly drawn Table 5-5 priority, node and duration."""
    instructions = []
    for k in range(count):
        priority = priorities[int(rng.integers(len(priorities)))]
        instructions.append(Instruction(
            id=k + 1, gamma=priority.gamma, beta=priority.beta,
            destination=int(rng.integers(node_count)),
            duration=int(rng.integers(config.duration_min_s, config.duration_max_s + 1)),
            start_time=0.0 if launches is None else float(launches[k])))
    return tuple(instructions)


def static_planners(config, trial, with_opt):
    """The planners of Table 5-7 (plus ours and the exact optimiser) for one trial; with
    `with_opt` also those run on a few sets only (the exhaustive Opt)."""
    uses = (BENCH_STATIC, BENCH_STATIC_FEW) if with_opt else (BENCH_STATIC,)
    return make_planners(uses, config.planner_settings(), seed=config.seed * 100003 + trial)


def planner_record(problem, schedule):
    """One planner's entry of the JSON schema."""
    return {
        "route": [int(n) for n in schedule.route],
        "served": [[int(problem.ids[i]), int(pos)] for i, pos in schedule.served],
        "reward": schedule_reward(problem, schedule),
        "reward_with_decision": schedule_reward(problem, schedule, with_decision=True),
        "completion_s": completion_time(schedule),
        "decision_s": float(schedule.decision_s),
    }


def instruction_record(instruction):
    return {"id": instruction.id, "gamma": instruction.gamma, "beta": instruction.beta,
            "node": instruction.destination, "duration_s": instruction.duration,
            "launch_s": instruction.start_time, "previous_id": instruction.previous_id}


def graph_record(graph, config):
    return {"nodes": list(graph.names), "edges": [list(e) for e in graph.edges()],
            "speed_mps": config.speed_mps, "start_node": config.start_node}


def json_document(graph, config, static_trials, dynamic_trials=(), named_record=None):
    """The re-scoring document: `graph` and `trials` follow the issue's schema exactly;
    `named_case` (the Table 5-6 set) is one more trial; `dynamic_trials` entries also carry
    `waits` ([route position, depart not before s]) because an idle robot waits for launches, and
    so does any record of a step planner that turned on an edge (a repeated node in its route
    costs no travel: the robot turned back to it)."""
    document = {"graph": graph_record(graph, config), "trials": list(static_trials),
                "dynamic_trials": list(dynamic_trials)}
    if named_record is not None:
        document["named_case"] = dict(named_record, name="Table 5-6")
    return document


def run_trial(problem, planners, keep_waits=False):
    """Run every planner on `problem`; returns (JSON trial record, {name: Schedule})."""
    schedules, records = {}, {}
    for planner in planners:
        schedule = run_planner(problem, planner)
        schedules[planner.name] = schedule
        records[planner.name] = planner_record(problem, schedule)
        if keep_waits or schedule.waits:  # a step planner's turns on an edge are waits
            records[planner.name]["waits"] = [[int(k), float(t)] for k, t in
                                              sorted(schedule.waits.items())]
        schedule.guard_activations = getattr(planner, "guard_activations", 0)
    trial = {"instructions": [instruction_record(i) for i in problem.instructions],
             "planners": records}
    return trial, schedules


def served_order(problem, schedule):
    return [int(problem.ids[i]) for i, _ in schedule.served]


def run_static(graph, priorities, config):
    """Table 5-7/5-9 shape: random sets of `static_count` instructions, all planners."""
    rng = np.random.default_rng(config.seed)
    trials, rows = [], []
    for trial in range(config.static_trials):
        instructions = random_instructions(rng, config.static_count, priorities, graph.size, config)
        problem = Problem(graph, instructions, config.speed_mps, config.start_node)
        record, schedules = run_trial(problem, static_planners(config, trial,
                                                               trial < config.opt_trials))
        trials.append(record)
        rows.append(_static_row(problem, record, schedules))
    return trials, rows


def _static_row(problem, record, schedules):
    """Per-planner figures of one static trial, relative to the exact optimum."""
    exact = label("exact_offline")
    best = record["planners"][exact]["reward"]
    exact_order = served_order(problem, schedules[exact])
    row = {}
    for name, entry in record["planners"].items():
        schedule = schedules[name]
        row[name] = dict(entry, similarity=similarity_cost(served_order(problem, schedule),
                                                           exact_order),
                         ratio_to_exact=entry["reward"] / best,
                         completion_with_decision_s=completion_time(schedule, True),
                         guard_activations=schedule.guard_activations)
    return row


def run_named_case(graph, config):
    """The seed's example set of Table 5-6 (nodes and durations drawn with a fixed seed)."""
    rng = np.random.default_rng(56)
    instructions = tuple(Instruction(
        id=k + 1, gamma=float(g), beta=b, destination=int(rng.integers(graph.size)),
        duration=int(rng.integers(config.duration_min_s, config.duration_max_s + 1)))
        for k, (g, b) in enumerate(TABLE_5_6))
    problem = Problem(graph, instructions, config.speed_mps, config.start_node)
    record, schedules = run_trial(problem, static_planners(config, 0, with_opt=True))
    return problem, record, schedules


def run_scaling(graph, priorities, config):
    """Fig. 5-8/5-9: processing time, time ratio and decision latency vs instruction count."""
    rng = np.random.default_rng(config.seed + 1)
    results = {}
    for count in config.scaling_counts:
        for trial in range(config.scaling_trials):
            instructions = random_instructions(rng, count, priorities, graph.size, config)
            problem = Problem(graph, instructions, config.speed_mps, config.start_node)
            for planner in make_planners((BENCH_SCALING,), config.planner_settings(), trial):
                schedule = run_planner(problem, planner)
                calls = np.array(schedule.decision_calls)
                entry = results.setdefault(planner.name, {}).setdefault(count, [])
                entry.append({
                    "total_s": completion_time(schedule, with_decision=True),
                    "time_ratio": time_ratio(float(problem.duration.sum()), schedule.decision_s,
                                             navigation_time(problem, schedule)),
                    "latency_mean_ms": 1e3 * float(calls.mean()),
                    "latency_median_ms": 1e3 * float(np.median(calls)),
                    "cpu_p99_ms": 1e3 * float(np.percentile(schedule.decision_cpu_calls, 99)),
                    "latency_p99_ms": 1e3 * float(np.percentile(calls, 99)),
                    "latency_max_ms": 1e3 * float(calls.max()),
                    "reward": schedule_reward(problem, schedule)})
    return results


def run_exact_scaling(graph, priorities, config):
    """Runtime of the exact optimiser vs instruction count, up to the first count it cannot
    solve within `exact_limit_s` on every trial."""
    rng = np.random.default_rng(config.seed + 2)
    results = []
    for count in config.exact_counts:
        times, solved = [], 0
        for _ in range(config.exact_trials):
            instructions = random_instructions(rng, count, priorities, graph.size, config)
            problem = Problem(graph, instructions, config.speed_mps, config.start_node)
            started = time.perf_counter()
            try:
                warm_exact_optimum(problem, max(config.exact_counts), config.rollout,
                                   config.exact_limit_s)
                solved += 1
            except SolverTimeout:
                pass
            times.append(time.perf_counter() - started)
        results.append({"count": count, "solved": solved, "trials": config.exact_trials,
                        "mean_s": float(np.mean(times)), "max_s": float(np.max(times))})
        if solved < config.exact_trials:
            break
    return results


def run_dynamic(graph, priorities, config):
    """Instructions launched over time (Poisson); reward counted from each launch."""
    rng = np.random.default_rng(config.seed + 3)
    trials, rows = [], []
    for trial in range(config.dynamic_trials):
        gaps = rng.exponential(config.dynamic_mean_gap_s, config.dynamic_count)
        launches = np.concatenate([[0.0], np.cumsum(gaps[1:])])
        instructions = random_instructions(rng, config.dynamic_count, priorities, graph.size,
                                           config, launches)
        problem = Problem(graph, instructions, config.speed_mps, config.start_node)
        planners = make_planners((BENCH_DYNAMIC,), config.planner_settings(), seed=trial)
        record, _ = run_trial(problem, planners, keep_waits=True)
        trials.append(record)
        rows.append(record["planners"])
    return trials, rows
