import numpy as np
import pytest
from planner_factories import make_instruction

from task_planner.graph import floyd_warshall
from task_planner.problem import Problem, schedule_reward
from task_planner.ripple_planner import (RipplePlanner, best_neighbour, expected_reward,
                                         ripple_field, value_iteration_step)
from task_planner.robot_state import state_at_node, step_adjacency
from task_planner.simulate import run_planner


def test_eq_4_4_sums_decayed_expected_rewards():
    # 2 * 0.9^2 + 8 * 0.98^4 = 1.62 + 7.37894528
    value = expected_reward(np.array([2.0, 8.0]), np.array([0.9, 0.98]), np.array([2, 4]), 1.0)
    assert value == pytest.approx(8.99894528)
    assert expected_reward(np.array([2.0]), np.array([0.9]), np.array([2]), 0.5) \
        == pytest.approx(2 * 0.9)


def test_eq_4_5_picks_the_best_candidate():
    assert best_neighbour(np.array([4, 7, 9]), [1.0, 3.0, 2.0]) == 7


def test_algorithm_4_2_on_a_line(line_graph):
    # A -1- B -2- C -3- D, 1 step = 1 m. Robot on B; instruction (2, 0.9) on A, (8, 0.98) on D.
    # toward A: arrives on A: 2 + 8 * 0.98^6 = 9.0867390470
    # toward C: state (B:1, C:1): A at 2 steps, D at 4: 2 * 0.9^2 + 8 * 0.98^4 = 8.99894528
    steps = step_adjacency(line_graph.adjacency, 1.0)
    shortest = floyd_warshall(steps)[0]
    n_hat, nxt, candidates, rewards = value_iteration_step(
        state_at_node(steps, 1), np.array([2.0, 8.0]), np.array([0.9, 0.98]), np.array([0, 3]),
        steps, shortest, 1.0)
    assert candidates.tolist() == [0, 2]
    assert rewards == pytest.approx([9.0867390470, 8.99894528])
    assert n_hat == 0 and nxt.node == 0
    # a stronger instruction on D turns the robot toward C (dynamic addition adds its ripple)
    n_hat, nxt, _, _ = value_iteration_step(
        state_at_node(steps, 1), np.array([2.0, 8.0, 8.0]), np.array([0.9, 0.98, 0.98]),
        np.array([0, 3, 3]), steps, shortest, 1.0)
    assert n_hat == 2 and nxt.vector.tolist() == [0, 1, 1, 0]


def test_ripple_field_depends_on_distance_only(line_graph):
    steps = step_adjacency(line_graph.adjacency, 1.0)
    shortest = floyd_warshall(steps)[0]
    field = ripple_field(np.array([2.0]), np.array([0.5]), np.array([1]), shortest, 1.0)
    assert field == pytest.approx([1.0, 2.0, 0.5, 0.0625])


def test_planner_serves_everything_and_scores(line_graph):
    instructions = (make_instruction(1, 0, 2.0, 0.9, 1), make_instruction(2, 3, 8.0, 0.98, 2))
    problem = Problem(line_graph, instructions, speed_mps=1.0, start_node=1)
    schedule = run_planner(problem, RipplePlanner(step_s=1.0))
    assert schedule.route == [1, 0, 1, 2, 3]
    assert schedule.served == [(0, 1), (1, 4)]
    # A done at 1 + 1 = 2 s; D reached at 2 + 6 = 8 s, done at 10 s
    assert schedule.completion.tolist() == [2.0, 10.0]
    assert schedule_reward(problem, schedule) == pytest.approx(2 * 0.9 ** 2 + 8 * 0.98 ** 10)


def test_loop_guard_follows_the_strongest_ripple(star_graph):
    instructions = (make_instruction(1, 1, 1.0, 0.9), make_instruction(2, 2, 5.0, 0.9))
    planner = RipplePlanner(step_s=1.0)
    planner.reset(Problem(star_graph, instructions, speed_mps=1.0, start_node=0))
    available = np.array([0, 1])
    planner.decide(0, 0.0, available)
    assert planner.guard_activations == 0
    assert planner.decide(0, 0.0, available) == ("move", 2)   # same node, same set: a loop
    assert planner.guard_activations == 1
