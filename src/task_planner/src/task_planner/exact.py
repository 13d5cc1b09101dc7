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

import numpy as np

from task_planner.baselines import PlannerTooLarge
from task_planner.problem import order_reward

_TOLERANCE = 1e-12  # rewards closer than this count as equal when pruning


class SolverTimeout(RuntimeError):
    """The exact optimiser ran past its time limit."""


def exact_optimum(problem, max_instructions=40, initial_order=None, time_limit_s=None):
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
    best_order = list(initial_order) if initial_order is not None else _greedy_order(problem)
    best_reward = order_reward(problem, best_order)
    deadline = None if time_limit_s is None else time.perf_counter() + time_limit_s
    layer = {(0, problem.start_node): [(0.0, 0.0, ())]}
    for _ in range(count):
        layer = _extend_layer(problem, layer, best_reward, deadline)
    for labels in layer.values():
        for _, reward, order in labels:
            if reward > best_reward + _TOLERANCE:
                best_reward, best_order = reward, list(order)
    return [int(i) for i in best_order]


def _extend_layer(problem, layer, best_reward, deadline):
    """All non-dominated, not-pruned labels with one more instruction served."""
    p = problem
    full = (1 << p.count) - 1
    predecessor_bit = [0 if k < 0 else 1 << int(k) for k in p.predecessor]
    nodes, durations, launches = p.node.tolist(), p.duration.tolist(), p.launch.tolist()
    gamma, beta = p.gamma, p.beta
    following = {}
    for (served, node), labels in layer.items():
        if deadline is not None and time.perf_counter() > deadline:
            raise SolverTimeout(f"exact optimiser: {p.count} instructions, time limit exceeded")
        remaining = [i for i in range(p.count) if not served >> i & 1]
        ready = [i for i in remaining if predecessor_bit[i] & served == predecessor_bit[i]]
        rem = np.array(remaining)
        offsets = _slot_offsets(p, node, rem)
        for clock, reward, order in labels:
            if reward + _reward_bound(p, node, rem, clock, offsets) < best_reward - _TOLERANCE:
                continue
            for i in ready:
                finish = max(clock + p.travel_s[node, nodes[i]], launches[i]) + durations[i]
                gain = gamma[i] * beta[i] ** (finish - launches[i])
                key = (served | 1 << i, nodes[i])
                _insert(following.setdefault(key, []), (finish, reward + gain, order + (i,)))
        if served == full:
            following[(served, node)] = labels
    return following


def _slot_offsets(problem, node, remaining):
    """Least time [s] after now by which k more services can be done, k = 1..len(remaining).

    Service i needs its duration plus the shortest drive into its node from the robot's node or
    from another remaining instruction's node; any k services need at least the k smallest.
    """
    p = problem
    nodes = p.node[remaining]
    between = p.travel_s[np.ix_(nodes, nodes)] + np.diag(np.full(len(nodes), np.inf))
    incoming = np.minimum(p.travel_s[node, nodes], between.min(axis=0))
    return np.cumsum(np.sort(p.duration[remaining] + incoming))


def _reward_bound(problem, node, remaining, clock, offsets):
    """Admissible bound on the reward still to come (the lesser of two relaxations).

    (a) each instruction served as if driven to directly next; (b) the k-th service ends no
    earlier than clock + offsets[k], and each such slot earns at most the best instruction's
    reward there.
    """
    p = problem
    launch, gamma, beta = p.launch[remaining], p.gamma[remaining], p.beta[remaining]
    direct = np.maximum(clock + p.travel_s[node, p.node[remaining]], launch) + p.duration[remaining]
    by_direct = float(np.sum(gamma * np.power(beta, direct - launch)))
    slots = np.maximum(direct[:, None], clock + offsets[None, :])
    by_slot = float(np.sum(np.max(gamma[:, None] * np.power(beta[:, None], slots - launch[:, None]),
                                  axis=0)))
    return min(by_direct, by_slot)


def _insert(labels, label):
    """Keep `labels` free of dominated (time, reward) pairs."""
    time, reward = label[0], label[1]
    for other in labels:
        if other[0] <= time and other[1] >= reward:
            return
    labels[:] = [o for o in labels if not (time <= o[0] and reward >= o[1])]
    labels.append(label)


def _greedy_order(problem):
    """A valid starting order: repeatedly the ready instruction with the best reward rate."""
    p = problem
    served, order, node, clock = set(), [], p.start_node, 0.0
    while len(order) < p.count:
        ready = [i for i in range(p.count) if i not in served
                 and (p.predecessor[i] < 0 or p.predecessor[i] in served)]
        finish = [max(clock + p.travel_s[node, p.node[i]], p.launch[i]) + p.duration[i]
                  for i in ready]
        rate = [p.gamma[i] * p.beta[i] ** (f - p.launch[i]) / max(f - clock, 1e-9)
                for i, f in zip(ready, finish)]
        pick = int(np.argmax(rate))
        order.append(ready[pick])
        served.add(ready[pick])
        node, clock = int(p.node[ready[pick]]), finish[pick]
    return order


class ExactReplanner:
    """Online use of the exact optimiser: re-solve over the known instructions whenever new ones
    have appeared, then serve the first instruction of the optimal order (a target planner).

    Rewards are counted from each launch, so at time `clock` an instruction launched at L is worth
    gamma * beta ** (clock - L) now: the sub-problem starts at the robot's node at t = 0 with those
    initial rewards.
    """

    name = "Exact-replan"

    def __init__(self, max_instructions=40):
        self.max_instructions = max_instructions

    def reset(self, problem):
        self.problem, self.plan, self.known = problem, [], frozenset()

    def choose(self, node, clock, available):
        known = frozenset(available.tolist())
        if not known <= self.known or not self.plan:
            self.plan = self._solve(node, clock, available)
            self.known = known
        for index in list(self.plan):
            self.plan.remove(index)
            if index in known:
                return index
        raise RuntimeError("exact replanner: no available instruction in its plan")

    def _solve(self, node, clock, available):
        from dataclasses import replace

        from task_planner.problem import Problem

        p = self.problem
        worth = np.maximum(p.gamma[available] * p.beta[available] ** (clock - p.launch[available]),
                           np.finfo(float).tiny)  # Instruction needs gamma > 0
        present = [replace(p.instructions[i], start_time=0.0, gamma=float(w), previous_id=0)
                   for i, w in zip(available, worth)]
        sub = Problem(p.graph, tuple(present), p.speed_mps, int(node))
        return [int(available[k]) for k in exact_optimum(sub, self.max_instructions)]
