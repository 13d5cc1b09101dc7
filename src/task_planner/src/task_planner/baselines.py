"""Classic planners of thesis 000 §5.3: FCFS, Rand, PF, SF and the exhaustive optimum Opt.

FCFS, Rand, PF and SF are dispatch rules: whenever the robot is free they pick the next
instruction among those launched and eligible; the robot then drives the shortest path to it and
serves it. Opt enumerates every order, as the seed did, and refuses sets above a size limit.
"""
import functools
import itertools
import math
from collections.abc import Callable, Iterable
from typing import ClassVar, Literal

import numpy as np

from task_planner.planner_api import TARGET
from task_planner.problem import Problem


class PlannerTooLarge(ValueError):
    """A planner was given more instructions than its configured limit."""


class FirstComeFirstServe:
    """FCFS: the earliest launched instruction (then the lowest id)."""

    kind: ClassVar[Literal["target"]] = TARGET
    problem: Problem
    name = "FCFS"

    def reset(self, problem: Problem) -> None:
        self.problem = problem

    def choose(self, node: int, clock: float, available: np.ndarray) -> int:
        p = self.problem
        return int(available[np.lexsort((p.ids[available], p.launch[available]))[0]])


class RandomOrder:
    """Rand: a uniformly random available instruction, from a seeded generator."""

    kind: ClassVar[Literal["target"]] = TARGET
    problem: Problem
    name = "Rand"

    def __init__(self, seed: int = 0) -> None:
        self.seed = seed

    def reset(self, problem: Problem) -> None:
        self.problem, self.rng = problem, np.random.default_rng(self.seed)

    def choose(self, node: int, clock: float, available: np.ndarray) -> int:
        return int(self.rng.choice(available))


class PriorityFirst:
    """PF: the highest initial reward gamma (ties: first come first served)."""

    kind: ClassVar[Literal["target"]] = TARGET
    problem: Problem
    name = "PF"

    def reset(self, problem: Problem) -> None:
        self.problem = problem

    def choose(self, node: int, clock: float, available: np.ndarray) -> int:
        p = self.problem
        keys = (p.ids[available], p.launch[available], -p.gamma[available])
        return int(available[np.lexsort(keys)[0]])


class ShortestTimeFirst:
    """SF: the least navigation time plus duration from the robot's node (ties: lowest id)."""

    kind: ClassVar[Literal["target"]] = TARGET
    problem: Problem
    name = "SF"

    def reset(self, problem: Problem) -> None:
        self.problem = problem

    def choose(self, node: int, clock: float, available: np.ndarray) -> int:
        p = self.problem
        cost = p.travel_s[node, p.node[available]] + p.duration[available]
        return int(available[np.lexsort((p.ids[available], cost))[0]])


class PlannedOrder:
    """Serves a whole order computed at the first decision by `solve(problem) -> order`."""

    kind: ClassVar[Literal["target"]] = TARGET
    problem: Problem
    order: list[int] | None

    def __init__(self, name: str, solve: Callable[[Problem], Iterable[int]]) -> None:
        self.name, self.solve = name, solve

    def reset(self, problem: Problem) -> None:
        self.problem, self.order = problem, None

    def choose(self, node: int, clock: float, available: np.ndarray) -> int:
        if self.order is None:
            self.order = list(self.solve(self.problem))
        for index in self.order:
            if index in available:
                self.order.remove(index)
                return int(index)
        raise RuntimeError("planned order has no available instruction left")


def exhaustive_optimum(problem: Problem, max_instructions: int = 10) -> list[int]:
    """Opt of §5.3.1: the best of all M! orders that respect `previous_id` chains.

    Raises PlannerTooLarge above `max_instructions` instead of exhausting memory or time.
    """
    count = problem.count
    if count > max_instructions:
        raise PlannerTooLarge(
            f"Opt: {count} instructions exceed the exhaustive limit of {max_instructions} "
            f"({math.factorial(count):.3g} orders); use the exact optimiser instead")
    if count == 0:
        return []
    best_reward, best_order = -1.0, None
    for head in itertools.permutations(range(count), min(2, count)):
        orders, rewards = _evaluate_permutations(problem, head)
        if len(rewards) and rewards.max() > best_reward:
            best_reward, best_order = rewards.max(), orders[int(np.argmax(rewards))]
    if best_order is None:
        raise ValueError("Opt: no order respects the previous_id chains")
    return [int(i) for i in best_order]


@functools.lru_cache(maxsize=4)
def _permutation_table(size: int) -> np.ndarray:
    """All permutations of range(size) as an int array (size!, size)."""
    return np.array(list(itertools.permutations(range(size))), dtype=int).reshape(
        math.factorial(size), size)


def _evaluate_permutations(problem: Problem,
                           head: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray]:
    """Rewards of every order starting with `head`, vectorised (chains filtered out)."""
    rest = np.array([i for i in range(problem.count) if i not in head], dtype=int)
    tails = rest[_permutation_table(len(rest))]
    orders = np.hstack([np.tile(head, (len(tails), 1)), tails])
    position = np.argsort(orders, axis=1)
    valid = np.ones(len(orders), bool)
    for i, pred in enumerate(problem.predecessor):
        if pred >= 0:
            valid &= position[:, pred] < position[:, i]
    orders = orders[valid]
    nodes = problem.node[orders]
    previous = np.hstack([np.full((len(orders), 1), problem.start_node), nodes[:, :-1]])
    travel = problem.travel_s[previous, nodes]
    launch, duration = problem.launch[orders], problem.duration[orders]
    completion = np.empty(orders.shape)
    clock = np.zeros(len(orders))
    for k in range(orders.shape[1]):  # an instruction starts no earlier than its launch
        clock = np.maximum(clock + travel[:, k], launch[:, k]) + duration[:, k]
        completion[:, k] = clock
    elapsed = completion - problem.launch[orders]
    rewards = np.sum(problem.gamma[orders] * np.power(problem.beta[orders], elapsed), axis=1)
    return orders, rewards
