"""The seed's task planner decided once per node: ripple-like expected reward and value
iteration (thesis 000 §4.2.3). `step_planner` decides at every step along the edges instead.

Every pending instruction spreads an expected reward gamma * beta ** t over the graph, t being the
step distance from its node (Fig. 4-6). The expansion depends on distance only and never on the
time since launch (§4.2.4: no starvation of old instructions). At each decision the planner scores
the state one step toward each neighbouring node by the accumulated expected reward (Eq. 4-4) and
drives the whole edge toward the best (Eq. 4-5, Algorithm 4-2). Instructions on the robot's node
are served at once, highest initial reward first.

Termination guard (ours): on a graph hub the accumulated field can peak away from any instruction
node; the seed's rule then steps out and back forever. Returning to a node already decided on with
the same instruction set proves such a loop, so from there the robot follows the single strongest
ripple term until the instruction set changes. `guard_activations` counts how often this happens.
"""
from collections.abc import Sequence
from typing import ClassVar, Literal

import numpy as np

from task_planner.graph import floyd_warshall
from task_planner.planner_api import NODE
from task_planner.problem import Problem
from task_planner.robot_state import (RobotState, neighbouring_nodes, state_at_node,
                                      state_transition, step_adjacency, steps_to_instructions)


def expected_reward(gamma: np.ndarray, beta: np.ndarray, steps: np.ndarray, step_s: float) -> float:
    """Eq. 4-4: r_{L+1} = sum_i gamma_i * beta_i ** t_i, t_i = steps from instruction i * step_s."""
    return float(np.sum(gamma * np.power(beta, steps * step_s)))


def best_neighbour(candidates: np.ndarray, rewards: Sequence[float]) -> int:
    """Eq. 4-5: the neighbouring node whose candidate step has the highest accumulated reward."""
    return int(candidates[int(np.argmax(rewards))])


def value_iteration_step(state: RobotState, gamma: np.ndarray, beta: np.ndarray, nodes: np.ndarray,
                         step_adj: np.ndarray, shortest_steps: np.ndarray,
                         step_s: float) -> tuple[int, RobotState, np.ndarray, list[float]]:
    """Algorithm 4-2: next neighbouring node, the state one step toward it, and all candidates.

    Returns (n_hat, next_state, candidates, candidate_rewards).
    """
    candidates = neighbouring_nodes(step_adj, state)
    states = [state_transition(step_adj, state, n) for n in candidates]
    rewards = [expected_reward(gamma, beta, steps_to_instructions(shortest_steps, c, nodes), step_s)
               for c in states]
    n_hat = best_neighbour(candidates, rewards)
    return n_hat, states[list(candidates).index(n_hat)], candidates, rewards


def ripple_field(gamma: np.ndarray, beta: np.ndarray, nodes: np.ndarray, shortest_steps: np.ndarray,
                 step_s: float) -> np.ndarray:
    """Fig. 4-6: expected reward on each node, sum_i gamma_i * beta_i ** (D[m_i][n] * step_s)."""
    exponents = shortest_steps[nodes, :] * step_s
    return np.sum(gamma[:, None] * np.power(beta[:, None], exponents), axis=0)


def step_graph(problem: Problem, step_s: float) -> tuple[np.ndarray, np.ndarray]:
    """(edge lengths in steps of speed * step_s metres, shortest paths in steps) of a problem's
    graph: the discretisation both readings of Algorithm 4-2 plan on."""
    step_adj = step_adjacency(problem.graph.adjacency, problem.speed_mps * step_s)
    return step_adj, floyd_warshall(step_adj)[0]


def serve_here(problem: Problem, available: np.ndarray, node: int) -> int | None:
    """The available instruction to serve on `node` first (highest initial reward, then id), or
    None when none waits there (the thesis gives no order)."""
    here = available[problem.node[available] == node]
    if not len(here):
        return None
    return int(here[np.lexsort((problem.ids[here], -problem.gamma[here]))[0]])


class RipplePlanner:
    """Per-node online planner of the seed (Algorithm 4-2) with the loop guard described above."""

    kind: ClassVar[Literal["node"]] = NODE
    name = "Ours(seed/node)"
    problem: Problem
    _visited: set[int]
    _known: frozenset[int] | None
    _locked: int | None

    def __init__(self, step_s: float = 1.0) -> None:
        self.step_s = step_s  # time step of the edge discretisation [s]

    def reset(self, problem: Problem) -> None:
        self.problem = problem
        self.step_adj, self.shortest_steps = step_graph(problem, self.step_s)
        self.guard_activations = 0
        self._visited, self._known, self._locked = set(), None, None

    def decide(self, node: int, clock: float,
               available: np.ndarray) -> tuple[Literal["serve", "move"], int]:
        """('serve', index) if an instruction waits on `node`, else ('move', neighbouring node)."""
        p = self.problem
        first = serve_here(p, available, node)
        if first is not None:
            return "serve", first
        known = frozenset(available.tolist())
        if known != self._known:
            self._visited, self._known, self._locked = set(), known, None
        if node in self._visited and self._locked is None:
            self.guard_activations += 1
            self._locked = self._strongest_term(node, available)
        self._visited.add(node)
        if self._locked is not None:
            return "move", int(p.graph.next_hop[node, p.node[self._locked]])
        n_hat, _, _, _ = value_iteration_step(
            state_at_node(self.step_adj, node), p.gamma[available], p.beta[available],
            p.node[available], self.step_adj, self.shortest_steps, self.step_s)
        return "move", n_hat

    def _strongest_term(self, node: int, available: np.ndarray) -> int:
        p = self.problem
        steps = self.shortest_steps[p.node[available], node] * self.step_s
        return int(available[np.argmax(p.gamma[available] * np.power(p.beta[available], steps))])
