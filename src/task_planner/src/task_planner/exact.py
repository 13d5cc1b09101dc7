"""Exact optimiser for the static problem: label-setting DP with dominance and a reward bound.

A label is (time, reward) after serving a set S of instructions and standing on node v. The best
future reward from (S, v, time) can only fall as time grows (each later completion decays), so a
label with no later time and no lower reward dominates another of the same (S, v). Labels are
extended one instruction at a time, layer by layer (|S| = 0, 1, ...). A label is also dropped when
its optimistic bound - its reward plus every remaining instruction served as if it were driven to
directly next - cannot beat the best complete order found so far (an admissible bound in the sense
of Reward-Maximising A*). The result is a provably optimal order over all orders respecting
`previous_id` chains; it equals the exhaustive Opt wherever Opt runs.
"""
import time
from collections.abc import Iterable, Sequence
from typing import ClassVar, Literal

import numpy as np

from task_planner.baselines import PlannerTooLarge
from task_planner.planner_api import TARGET
from task_planner.problem import Problem, order_reward
from task_planner.rollout_planner import RolloutConfig, RolloutPlanner
from task_planner.simulate import run_planner

_TOLERANCE = 1e-12  # rewards closer than this count as equal when pruning
_GREEDY_PROBES = 4  # labels per layer completed greedily to improve the incumbent

Label = tuple[float, float, tuple[int, ...]]  # (clock [s], reward so far, order served)
FlatLabel = tuple[int, int, Label]            # (served set as bits, node, label)
Layer = dict[tuple[int, int], list[Label]]    # (served set as bits, node) -> its labels


class SolverTimeout(RuntimeError):
    """The exact optimiser ran past its time limit."""


def exact_optimum(problem: Problem, max_instructions: int = 40,
                  initial_order: Iterable[int] | None = None,
                  time_limit_s: float | None = None) -> list[int]:
    """Provably optimal service order (list of instruction indices) of a static problem.

    Args:
        max_instructions: refuse larger sets (PlannerTooLarge): the worst case is exponential.
        initial_order: any valid order; its reward seeds the pruning bound.
        time_limit_s: raise SolverTimeout when the search runs longer [s]; None = no limit.
    """
    count = problem.count
    if count > max_instructions:
        raise PlannerTooLarge(f"exact optimiser: {count} instructions exceed the limit of "
                              f"{max_instructions}")
    if count == 0:
        return []
    best_order = list(initial_order) if initial_order is not None else _greedy_order(problem)[0]
    best_reward = order_reward(problem, best_order)
    deadline = None if time_limit_s is None else time.perf_counter() + time_limit_s
    layer: Layer = {(0, problem.start_node): [(0.0, 0.0, ())]}
    for _ in range(count):
        layer, promising = _extend_layer(problem, layer, best_reward, deadline)
        for served, node, (clock, reward, order) in promising:  # better incumbents prune more
            rest, total = _greedy_order(problem, order, node, clock, reward)
            if total > best_reward + _TOLERANCE:
                best_reward, best_order = total, list(order) + rest
    for labels in layer.values():
        for _, reward, order in labels:
            if reward > best_reward + _TOLERANCE:
                best_reward, best_order = reward, list(order)
    return [int(i) for i in best_order]


def warm_exact_optimum(problem: Problem, max_instructions: int = 40,
                       rollout: RolloutConfig | None = None,
                       time_limit_s: float | None = None) -> list[int]:
    """`exact_optimum` with its pruning bound seeded by the order the rollout planner serves
    (`rollout`: its RolloutConfig, None for the defaults)."""
    warm = run_planner(problem, RolloutPlanner(rollout))
    return exact_optimum(problem, max_instructions, [i for i, _ in warm.served], time_limit_s)


def _extend_layer(problem: Problem, layer: Layer, best_reward: float,
                  deadline: float | None) -> tuple[Layer, list[FlatLabel]]:
    """All non-dominated, not-pruned labels with one more instruction served."""
    p = problem
    flat = [(served, node, label) for (served, node), labels in layer.items() for label in labels]
    bounds = _layer_bounds(p, flat, deadline)
    dropped = _delay_dominated(p, flat, bounds)
    predecessor_bit = [0 if k < 0 else 1 << int(k) for k in p.predecessor]
    nodes, durations, launches = p.node.tolist(), p.duration.tolist(), p.launch.tolist()
    gamma, beta, travel = p.gamma.tolist(), p.beta.tolist(), p.travel_s.tolist()
    following: Layer = {}
    for (served, node, (clock, reward, order)), bound, drop in zip(flat, bounds, dropped):
        if drop or reward + bound < best_reward - _TOLERANCE:
            continue
        for i in range(p.count):
            if served >> i & 1 or predecessor_bit[i] & served != predecessor_bit[i]:
                continue
            finish = max(clock + travel[node][nodes[i]], launches[i]) + durations[i]
            gain = gamma[i] * beta[i] ** (finish - launches[i])
            key = (served | 1 << i, nodes[i])
            _insert(following.setdefault(key, []), (finish, reward + gain, order + (i,)))
    ranked = np.argsort(-(np.array([label[1] for _, _, label in flat]) + bounds))
    promising = [flat[k] for k in ranked[:_GREEDY_PROBES] if not dropped[k]]
    return following, promising


def _delay_dominated(problem: Problem, flat: Sequence[FlatLabel], bounds: np.ndarray) -> np.ndarray:
    """Mark labels that a later, richer label of the same (set, node) provably matches.

    Starting Delta seconds later scales every future reward by at least beta_min ** Delta (the
    same plan, shifted), so a label A with time t_A > t_B is at least as good as B in total if
    r_A - r_B >= (1 - beta_min ** (t_A - t_B)) * bound_B, bound_B being B's admissible bound.
    """
    dropped = np.zeros(len(flat), dtype=bool)
    groups: dict[tuple[int, int], list[int]] = {}
    for k, (served, node, _) in enumerate(flat):
        groups.setdefault((served, node), []).append(k)
    for (served, _), members in groups.items():
        if len(members) < 2:
            continue
        left = [i for i in range(problem.count) if not served >> i & 1]
        beta_min = float(problem.beta[left].min()) if left else 1.0
        for b in members:
            time_b, reward_b = flat[b][2][0], flat[b][2][1]
            dropped[b] = any(
                flat[a][2][0] > time_b and flat[a][2][1] - reward_b
                >= (1.0 - beta_min ** (flat[a][2][0] - time_b)) * bounds[b]
                for a in members if a != b and not dropped[a])
    return dropped


def _layer_bounds(problem: Problem, flat: Sequence[FlatLabel], deadline: float | None,
                  chunk: int = 1024) -> np.ndarray:
    """Admissible bounds on the reward still to come, for every label of a layer (numpy)."""
    p = problem
    bits = 1 << np.arange(p.count, dtype=object)
    bounds = []
    for begin in range(0, len(flat), chunk):
        if deadline is not None and time.perf_counter() > deadline:
            raise SolverTimeout(f"exact optimiser: {p.count} instructions, time limit exceeded")
        part = flat[begin:begin + chunk]
        served = np.array([[(s & b) != 0 for b in bits] for s, _, _ in part], dtype=bool)
        nodes = np.array([n for _, n, _ in part], dtype=int)
        clock = np.array([label[0] for _, _, label in part])
        bounds.append(_reward_bounds(p, ~served, nodes, clock))
    return np.concatenate(bounds) if bounds else np.zeros(0)


def _reward_bounds(problem: Problem, remaining: np.ndarray, nodes: np.ndarray,
                   clock: np.ndarray) -> np.ndarray:
    """The lesser of two relaxations of the reward still to come, per label (rows).

    (a) each remaining instruction served as if driven to directly next; (b) the k-th service ends
    no earlier than clock + the k smallest (duration + shortest drive into its node from the
    robot's node or another remaining instruction's node), and each such slot earns at most the
    best remaining instruction's reward there.
    """
    p = problem
    gamma, beta, launch = p.gamma, p.beta, p.launch
    drive = p.travel_s[nodes][:, p.node]                                   # (L, M)
    direct = np.maximum(clock[:, None] + drive, launch) + p.duration
    by_direct = np.where(remaining, gamma * np.power(beta, direct - launch), 0.0).sum(axis=1)
    between = p.travel_s[np.ix_(p.node, p.node)] + np.diag(np.full(p.count, np.inf))
    from_others = np.where(remaining[:, :, None], between[None], np.inf).min(axis=1)
    cost = np.where(remaining, p.duration + np.minimum(drive, from_others), np.inf)
    slots = clock[:, None] + np.cumsum(np.sort(cost, axis=1), axis=1)       # (L, K), inf unused
    times = np.maximum(direct[:, :, None], slots[:, None, :])              # (L, M, K)
    values = gamma[None, :, None] * np.power(beta[None, :, None], times - launch[None, :, None])
    by_slot = np.where(remaining[:, :, None], values, 0.0).max(axis=1).sum(axis=1)
    return np.minimum(by_direct, by_slot)


def _insert(labels: list[Label], label: Label) -> None:
    """Keep `labels` free of dominated (time, reward) pairs."""
    time, reward = label[0], label[1]
    for other in labels:
        if other[0] <= time and other[1] >= reward:
            return
    labels[:] = [o for o in labels if not (time <= o[0] and reward >= o[1])]
    labels.append(label)


def _greedy_order(problem: Problem, served: Iterable[int] = (), node: int | None = None,
                  clock: float = 0.0, reward: float = 0.0) -> tuple[list[int], float]:
    """Complete a partial order by the reward-rate rule; returns (order of the rest, total reward).

    Args:
        served: instructions already served; node, clock, reward: where that left the robot.
    """
    p = problem
    served, order = set(served), []
    node = p.start_node if node is None else node
    while len(served) < p.count:
        ready = [i for i in range(p.count) if i not in served
                 and (p.predecessor[i] < 0 or p.predecessor[i] in served)]
        finish = [max(clock + p.travel_s[node, p.node[i]], p.launch[i]) + p.duration[i]
                  for i in ready]
        gains = [p.gamma[i] * p.beta[i] ** (f - p.launch[i]) for i, f in zip(ready, finish)]
        pick = int(np.argmax([g / max(f - clock, 1e-9) for g, f in zip(gains, finish)]))
        order.append(ready[pick])
        served.add(ready[pick])
        node, clock, reward = int(p.node[ready[pick]]), finish[pick], reward + gains[pick]
    return order, reward


class ExactReplanner:
    """Online use of the exact optimiser: re-solve over the known instructions whenever new ones
    have appeared, then serve the first instruction of the optimal order (a target planner).

    Rewards are counted from each launch, so at time `clock` an instruction launched at L is worth
    gamma * beta ** (clock - L) now: the sub-problem starts at the robot's node at t = 0 with those
    initial rewards.
    """

    kind: ClassVar[Literal["target"]] = TARGET
    name = "Exact-replan"
    problem: Problem
    plan: list[int]
    known: frozenset[int]

    def __init__(self, max_instructions: int = 40) -> None:
        self.max_instructions = max_instructions

    def reset(self, problem: Problem) -> None:
        self.problem, self.plan, self.known = problem, [], frozenset()

    def choose(self, node: int, clock: float, available: np.ndarray) -> int:
        known = frozenset(available.tolist())
        if not known <= self.known or not self.plan:
            self.plan = self._solve(node, clock, available)
            self.known = known
        for index in list(self.plan):
            self.plan.remove(index)
            if index in known:
                return index
        raise RuntimeError("exact replanner: no available instruction in its plan")

    def _solve(self, node: int, clock: float, available: np.ndarray) -> list[int]:
        from dataclasses import replace

        from task_planner.problem import Problem

        p = self.problem
        worth = np.maximum(p.gamma[available] * p.beta[available] ** (clock - p.launch[available]),
                           np.finfo(float).tiny)  # Instruction needs gamma > 0
        present = [replace(p.instructions[i], start_time=0.0, gamma=float(w), previous_id=0)
                   for i, w in zip(available, worth)]
        sub = Problem(p.graph, tuple(present), p.speed_mps, int(node))
        return [int(available[k]) for k in exact_optimum(sub, self.max_instructions)]
