"""Algorithm 4-2 as the thesis writes it: one decision per step, on edges too (thesis 000 §4.2.3).

Edges are cut into steps of `speed * step_s` metres (`robot_state`). At every step the planner
takes the robot's state vector s_t, forms the candidate state c_n = state_transition(s_t, n) for
each neighbouring node n (lines 3-7: a node's neighbours, or the two ends of the robot's edge),
scores each candidate by the accumulated expected reward of Eq. 4-4 (lines 8-11) and steps to
the best (Eq. 4-5, lines 12-13). On an edge the neighbours are the edge's ends, so the robot
turns back mid-edge when an arriving instruction makes the node behind it worth more.

Accumulated values on nodes are memorised (§4.2.3): `RippleField` holds sum_i gamma_i beta_i^t
for every node, adds an instruction's ripple when it arrives and removes it when it is served. A
candidate on a node reads its memorised value; a candidate on an edge is scored by Eq. 4-4 with
t_i = min(k + a, l + b) over the edge's ends.

Serving: on a node where available instructions wait the robot serves them before it steps on,
highest initial reward first (the thesis gives no order; the per-node variant does the same).

Loop guard (ours, as in `ripple_planner`): where the accumulated field peaks on a node with no
instruction, Eq. 4-5 steps out and back forever. The planner is deterministic, so reaching a
state it already decided in with the same instruction set proves such a loop; from there it
steps along the shortest path to the single strongest ripple term until the set changes.
"""
from typing import ClassVar, Literal

import numpy as np

from task_planner.planner_api import STEP
from task_planner.problem import Problem
from task_planner.ripple_planner import best_neighbour, expected_reward, serve_here, step_graph
from task_planner.robot_state import (RobotState, neighbouring_nodes, state_at_node,
                                      state_transition, steps_to_instructions)


class RippleField:
    """Memorised accumulated expected reward on every node (§4.2.3, Fig. 4-6).

    `values[n]` = sum over the held instructions of gamma * beta ** (D[m][n] * step_s), D in
    steps. Arriving instructions add their ripple, served ones subtract it.
    """

    def __init__(self, shortest_steps: np.ndarray, step_s: float) -> None:
        self.shortest_steps, self.step_s = shortest_steps, step_s
        self.values = np.zeros(len(shortest_steps))
        self._terms: dict[int, np.ndarray] = {}  # instruction index -> its ripple on every node

    def sync(self, indices: np.ndarray, gamma: np.ndarray, beta: np.ndarray,
             node: np.ndarray) -> None:
        """Hold exactly the instructions `indices` (arrays indexed by instruction index)."""
        wanted = set(int(i) for i in indices)
        for index in set(self._terms) - wanted:
            self.values -= self._terms.pop(index)
        for index in sorted(wanted - set(self._terms)):
            term = gamma[index] * np.power(beta[index],
                                           self.shortest_steps[node[index]] * self.step_s)
            self._terms[index] = term
            self.values += term

    def held(self) -> list[int]:
        return sorted(self._terms)


def candidate_value(field: RippleField, state: RobotState, gamma: np.ndarray, beta: np.ndarray,
                    nodes: np.ndarray) -> float:
    """Eq. 4-4 for one candidate state: the memorised node value, or on an edge
    sum_i gamma_i * beta_i ** (min(k + a, l + b) * step_s) over the held instructions."""
    if state.node is not None:
        return float(field.values[state.node])
    steps = steps_to_instructions(field.shortest_steps, state, nodes)
    return expected_reward(gamma, beta, steps, field.step_s)


def per_step_decision(field: RippleField, state: RobotState, step_adj: np.ndarray,
                      gamma: np.ndarray, beta: np.ndarray,
                      nodes: np.ndarray) -> tuple[int, RobotState, np.ndarray, list[float]]:
    """Algorithm 4-2 lines 5-13 at state s_t: (n_hat, c_n_hat, candidates, candidate values)."""
    candidates = neighbouring_nodes(step_adj, state)
    states = [state_transition(step_adj, state, n) for n in candidates]
    values = [candidate_value(field, c, gamma, beta, nodes) for c in states]
    n_hat = best_neighbour(candidates, values)
    return n_hat, states[list(candidates).index(n_hat)], candidates, values


class StepRipplePlanner:
    """The seed's planner deciding at every step of every edge (Algorithm 4-2, §4.2.3)."""

    kind: ClassVar[Literal["step"]] = STEP
    name = "Ours(seed/step)"
    problem: Problem
    _visited: set[tuple[int | None, tuple[int, ...]]]
    _known: frozenset[int] | None
    _locked: int | None

    def __init__(self, step_s: float = 1.0) -> None:
        self.step_s = step_s  # time step of the edge discretisation [s]

    def reset(self, problem: Problem) -> None:
        self.problem = problem
        self.step_adj, self.shortest_steps = step_graph(problem, self.step_s)
        self.field = RippleField(self.shortest_steps, self.step_s)
        self.guard_activations = 0
        self._visited, self._known, self._locked = set(), None, None

    def start_state(self) -> RobotState:
        """The robot's state vector on the problem's start node."""
        return state_at_node(self.step_adj, self.problem.start_node)

    def decide(self, state: RobotState, clock: float,
               available: np.ndarray) -> tuple[Literal["serve", "step"], int]:
        """('serve', index) if an instruction waits on the robot's node, else ('step', n): one
        step toward neighbouring node n (`state_transition(step_adj, state, n)` is the next
        state)."""
        p = self.problem
        first = None if state.node is None else serve_here(p, available, state.node)
        if first is not None:
            return "serve", first
        self.field.sync(available, p.gamma, p.beta, p.node)
        known = frozenset(available.tolist())
        if known != self._known:
            self._visited, self._known, self._locked = set(), known, None
        key = (state.node, tuple(state.vector.tolist()))
        if key in self._visited and self._locked is None:
            self.guard_activations += 1
            self._locked = self._strongest_term(state, available)
        self._visited.add(key)
        if self._locked is not None:
            return "step", self._toward(state, self._locked)
        n_hat, _, _, _ = per_step_decision(self.field, state, self.step_adj, p.gamma[available],
                                           p.beta[available], p.node[available])
        return "step", n_hat

    def _strongest_term(self, state: RobotState, available: np.ndarray) -> int:
        p = self.problem
        steps = steps_to_instructions(self.shortest_steps, state, p.node[available])
        return int(available[np.argmax(p.gamma[available]
                                       * np.power(p.beta[available], steps * self.step_s))])

    def _toward(self, state: RobotState, index: int) -> int:
        """The neighbouring node whose candidate state is fewest steps from instruction `index`."""
        target = np.array([self.problem.node[index]])
        candidates = neighbouring_nodes(self.step_adj, state)
        steps = [steps_to_instructions(self.shortest_steps,
                                       state_transition(self.step_adj, state, n), target)[0]
                 for n in candidates]
        return int(candidates[int(np.argmin(steps))])
