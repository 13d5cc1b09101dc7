import numpy as np
import pytest

from task_planner.graph import floyd_warshall
from task_planner.robot_state import (state_at_node, state_transition, step_adjacency,
                                      steps_to_instructions)

# Fig. 4-7-like example: A-B 3 steps, B-C 2 steps, A-C 4 steps (step = 0.5 m)
ADJ_M = np.array([[0, 1.5, 2.0], [1.5, 0, 1.0], [2.0, 1.0, 0]])
A, B, C = 0, 1, 2


@pytest.fixture
def steps():
    return step_adjacency(ADJ_M, 0.5)


def test_step_adjacency(steps):
    assert steps.tolist() == [[0, 3, 4], [3, 0, 2], [4, 2, 0]]


def test_case_3_leaving_a_node(steps):
    state = state_transition(steps, state_at_node(steps, A), B)
    assert state.vector.tolist() == [1, 2, 0] and state.node is None


def test_case_1_moving_along_the_edge(steps):
    state = state_transition(steps, state_at_node(steps, A), B)
    state = state_transition(steps, state, B)
    assert state.vector.tolist() == [2, 1, 0]
    back = state_transition(steps, state, A)
    assert back.vector.tolist() == [1, 2, 0]


def test_case_2_arriving_copies_the_adjacency_row(steps):
    state = state_at_node(steps, A)
    for _ in range(3):
        state = state_transition(steps, state, B)
    assert state.node == B and state.vector.tolist() == [3, 0, 2]
    returned = state_transition(steps, state_transition(steps, state_at_node(steps, A), B), A)
    assert returned.node == A and returned.vector.tolist() == [0, 3, 4]


def test_one_step_edge_arrives_at_once(steps):
    short = step_adjacency(np.array([[0, 0.5], [0.5, 0]]), 0.5)
    state = state_transition(short, state_at_node(short, 0), 1)
    assert state.node == 1 and state.vector.tolist() == [1, 0]


def test_stepping_toward_a_non_neighbour_fails(steps):
    with pytest.raises(ValueError, match="not an end"):
        state_transition(steps, state_transition(steps, state_at_node(steps, A), B), C)


def test_distance_from_an_edge_state(steps):
    shortest = floyd_warshall(steps)[0]
    on_edge = state_transition(steps, state_at_node(steps, A), B)   # 1 from A, 2 from B
    # instruction at C: min(D[C][A] + 1, D[C][B] + 2) = min(5, 4) = 4; at A: 1; at B: 2
    assert steps_to_instructions(shortest, on_edge, np.array([C, A, B])).tolist() == [4, 1, 2]
    at_b = state_at_node(steps, B)
    assert steps_to_instructions(shortest, at_b, np.array([A, B, C])).tolist() == [3, 0, 2]
