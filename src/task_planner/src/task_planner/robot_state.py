"""Robot-state vector on the topological graph (thesis 000 §4.2.3, Fig. 4-7(d)).

Edges are cut into steps of `speed * step_s` metres, so an edge weighs an integer number of
steps. The state is a |V| integer vector: at node i it is row i of the step adjacency matrix
(distance in steps to each neighbour, 0 elsewhere); on the edge i-j it holds the remaining steps to
i and to j and 0 elsewhere. The seed's text words case 1 as "the i-th element plus one"; we apply
the reading consistent with its cases 2 and 3: moving toward n decrements element n and increments
the other end, and reaching 0 means arriving. `node` records the node the robot stands on (None on
an edge), because a node with two neighbours can have the same vector as a point on an edge.
"""
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RobotState:
    vector: np.ndarray  # (V,) int: steps to the relevant nodes (see module docstring)
    node: int | None = None  # node index when standing on a node, None on an edge

    def support(self) -> np.ndarray:
        """Nodes the robot's distance is measured from: its node, or the two edge ends."""
        if self.node is not None:
            return np.array([self.node])
        return np.flatnonzero(self.vector)


def step_adjacency(adjacency_m: np.ndarray, step_m: float) -> np.ndarray:
    """Edge lengths [m] -> whole steps of `step_m` metres (at least 1 per edge); 0 = no edge."""
    steps = np.where(adjacency_m > 0, np.maximum(1, np.rint(adjacency_m / step_m)), 0)
    return steps.astype(int)


def state_at_node(step_adj: np.ndarray, node: int) -> RobotState:
    """Case 2 result: standing on `node`, the state is row `node` of the step adjacency matrix."""
    return RobotState(step_adj[node].copy(), int(node))


def leave_node(step_adj: np.ndarray, state: RobotState, target: int) -> RobotState:
    """Case 3: leaving node i toward neighbour j: element i becomes 1, j = A[i][j] - 1, others 0."""
    i = state.node
    if step_adj[i, target] == 0:
        raise ValueError(f"node {target} is not a neighbour of node {i}")
    vector = np.zeros_like(state.vector)
    vector[i] = 1
    vector[target] = step_adj[i, target] - 1
    return _arrive_if_zero(step_adj, vector, target)


def step_along_edge(step_adj: np.ndarray, state: RobotState, target: int) -> RobotState:
    """Case 1: on the edge, one step toward end `target`; the other non-zero end grows by one."""
    ends = np.flatnonzero(state.vector)
    if target not in ends:
        raise ValueError(f"node {target} is not an end of the robot's edge {tuple(ends)}")
    vector = state.vector.copy()
    other = ends[ends != target]
    vector[target] -= 1
    vector[other] += 1
    return _arrive_if_zero(step_adj, vector, target)


def _arrive_if_zero(step_adj: np.ndarray, vector: np.ndarray, target: int) -> RobotState:
    """Case 2: the element of `target` reached 0, so the robot is on `target`."""
    if vector[target] == 0:
        return state_at_node(step_adj, target)
    return RobotState(vector, None)


def state_transition(step_adj: np.ndarray, state: RobotState, target: int) -> RobotState:
    """Algorithm 4-2 line 7: the state after one step toward neighbouring node `target`."""
    if state.node is not None:
        return leave_node(step_adj, state, target)
    return step_along_edge(step_adj, state, target)


def neighbouring_nodes(step_adj: np.ndarray, state: RobotState) -> np.ndarray:
    """Algorithm 4-2 line 3: the nodes the robot can step toward."""
    if state.node is not None:
        return np.flatnonzero(step_adj[state.node])
    return np.flatnonzero(state.vector)


def steps_to_instructions(shortest_steps: np.ndarray, state: RobotState,
                          instruction_nodes: np.ndarray) -> np.ndarray:
    """Algorithm 4-2 line 9: min over the state's support n of (A[m_i][n] + s[n]) for each i."""
    support = state.support()
    via = shortest_steps[np.ix_(instruction_nodes, support)] + state.vector[support][None, :]
    return via.min(axis=1)
