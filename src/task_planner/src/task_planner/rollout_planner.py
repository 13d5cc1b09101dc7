"""Improved online planner (ours): the seed's per-node decision, with rollouts looking ahead.

At every node the planner takes the `candidates` available instructions that look best as the next
one (reward rate of going there directly), and for each simulates serving it first and then
`horizon - 1` more instructions by the reward-rate rule (the most decayed reward per second of
travel and service). Instructions left beyond the horizon add their optimistic value (each driven
to directly next, the ripple value of Eq. 4-4 with time decay), scaled by `tail_weight`. The
planner serves the best candidate if it waits on this node, else moves one node along the
shortest path toward it, and decides again at the next node, so new instructions count at once.
All rollouts of one decision run together as numpy arrays.
"""
from dataclasses import dataclass

from typing import ClassVar, Literal

import numpy as np

from task_planner.planner_api import NODE
from task_planner.problem import Problem

_MIN_STEP_S = 1e-9  # guards the reward rate when an instruction takes no time


@dataclass
class RolloutConfig:
    candidates: int = 6       # first instructions examined per decision
    horizon: int = 10         # instructions simulated per rollout (first one included)
    tail_weight: float = 0.5  # weight of the optimistic value of instructions beyond the horizon
    priority_first_at_node: bool = True  # at a node, serve the highest γ waiting there first


class RolloutPlanner:
    """Per-node online planner: rollouts of the reward-rate rule from the best first targets."""

    kind: ClassVar[Literal["node"]] = NODE
    name = "Ours(rollout)"

    def __init__(self, config: RolloutConfig | None = None) -> None:
        self.config = config or RolloutConfig()

    def reset(self, problem: Problem) -> None:
        self.problem = problem

    def decide(self, node: int, clock: float,
               available: np.ndarray) -> tuple[Literal["serve", "move"], int]:
        target = self.best_first(node, clock, available)
        if self.problem.node[target] == node:
            return "serve", self._first_at_node(node, target, available)
        return "move", int(self.problem.graph.next_hop[node, self.problem.node[target]])

    def _first_at_node(self, node: int, target: int, available: np.ndarray) -> int:
        """The seed's rule at a node (§4.2.4: highest γ first), kept when `priority_first_at_node`:
        nobody waiting here is passed over for a lower-priority request at the same place, even
        when serving the shorter one first would earn more reward. Ties keep the rollout's choice.
        """
        p = self.problem
        if not self.config.priority_first_at_node:
            return target
        here = available[p.node[available] == node]
        best = here[p.gamma[here] > p.gamma[target]]
        return int(best[np.argmax(p.gamma[best])]) if len(best) else target

    def best_first(self, node: int, clock: float, available: np.ndarray) -> int:
        """The available instruction whose rollout earns the most."""
        p, cfg = self.problem, self.config
        finish = np.maximum(clock + p.travel_s[node, p.node[available]], p.launch[available]) \
            + p.duration[available]
        rate = _reward(p, available, finish) / np.maximum(finish - clock, _MIN_STEP_S)
        firsts = np.argsort(-rate, kind="stable")[:cfg.candidates]
        if len(available) == 1:
            return int(available[0])
        values = self._rollouts(node, clock, available, firsts)
        return int(available[firsts[int(np.argmax(values))]])

    def _rollouts(self, node: int, clock: float, available: np.ndarray,
                  firsts: np.ndarray) -> np.ndarray:
        """Reward of each rollout (one row per first choice), plus the weighted tail."""
        p, cfg = self.problem, self.config
        rows = np.arange(len(firsts))
        nodes, launch = p.node[available], p.launch[available]
        served = np.zeros((len(firsts), len(available)), bool)
        current = np.full(len(firsts), node)
        clocks = np.full(len(firsts), float(clock))
        total = np.zeros(len(firsts))
        choice = firsts
        for step in range(min(cfg.horizon, len(available))):
            finish = np.maximum(clocks[:, None] + p.travel_s[current][:, nodes], launch) \
                + p.duration[available]
            value = _reward(p, available, finish)
            if step:
                rate = value / np.maximum(finish - clocks[:, None], _MIN_STEP_S)
                rate[served] = -np.inf
                choice = np.argmax(rate, axis=1)
            total += value[rows, choice]
            clocks, current = finish[rows, choice], nodes[choice]
            served[rows, choice] = True
        finish = np.maximum(clocks[:, None] + p.travel_s[current][:, nodes], launch) \
            + p.duration[available]
        tail = np.where(served, 0.0, _reward(p, available, finish)).sum(axis=1)
        return total + cfg.tail_weight * tail


def _reward(problem: Problem, indices: np.ndarray, finish: np.ndarray) -> np.ndarray:
    """Eq. 4-2 for instructions `indices` completed at `finish` (broadcast over rows)."""
    p = problem
    return p.gamma[indices] * np.power(p.beta[indices], finish - p.launch[indices])
