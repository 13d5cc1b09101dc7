import numpy as np
import pytest
from planner_factories import make_instruction
from test_planners import random_problem

from task_planner.exact import _greedy_order, exact_optimum
from task_planner.graph import graph_from_edges
from task_planner.problem import Problem, order_reward, schedule_reward
from task_planner.rollout_planner import RolloutConfig, RolloutPlanner
from task_planner.simulate import run_planner


def test_rollout_never_loses_to_its_base_rule():
    """With the horizon covering the set, a rollout policy earns at least its base policy (the
    at-node priority rule off: it may trade reward for not making a higher priority wait)."""
    graph = graph_from_edges(range(5), [(0, 1, 3.0), (1, 2, 4.0), (1, 3, 2.5), (3, 4, 6.0)])
    rng = np.random.default_rng(11)
    gains = []
    for _ in range(60):
        problem = random_problem(rng, graph, int(rng.integers(2, 9)))
        base, _ = _greedy_order(problem)
        pure = RolloutPlanner(RolloutConfig(priority_first_at_node=False))
        rollout = schedule_reward(problem, run_planner(problem, pure))
        assert rollout >= order_reward(problem, base) - 1e-9
        gains.append(rollout / order_reward(problem, exact_optimum(problem)))
    assert np.mean(gains) > 0.97


def test_rollout_looks_past_the_nearest_reward(line_graph):
    # A -1- B -2- C -3- D, robot on B, 1 m/s. A small reward next door (A) and a large, fast
    # decaying one far away (D): the rate rule goes to A first (0.9^1 / 1 s beats 8 * 0.8^5 / 5 s),
    # but going to D first earns 8 * 0.8^5 + 1 * 0.9^11 = 2.9353 > 0.9 + 8 * 0.8^7 = 2.5777.
    instructions = (make_instruction(1, 0, 1.0, 0.9), make_instruction(2, 3, 8.0, 0.8))
    problem = Problem(line_graph, instructions, speed_mps=1.0, start_node=1)
    schedule = run_planner(problem, RolloutPlanner(RolloutConfig(candidates=2, horizon=2)))
    assert [i for i, _ in schedule.served] == [1, 0]
    assert schedule_reward(problem, schedule) == pytest.approx(8 * 0.8 ** 5 + 0.9 ** 11)
    assert _greedy_order(problem)[0] == [0, 1]


def test_a_higher_priority_waiting_at_the_node_is_served_first(line_graph):
    # Both wait on B, where the robot is. Serving the short γ 3 check first earns more:
    # 3 * 0.94^20 + 5 * 0.96^80 = 1.0580 against 5 * 0.96^60 + 3 * 0.94^80 = 0.4426, so the pure
    # rollout serves it first; with the seed's at-node rule the γ 5 chat goes first.
    instructions = (make_instruction(1, 1, 3.0, 0.94, duration=20),
                    make_instruction(2, 1, 5.0, 0.96, duration=60))
    problem = Problem(line_graph, instructions, speed_mps=1.0, start_node=1)
    pure = run_planner(problem, RolloutPlanner(RolloutConfig(priority_first_at_node=False)))
    assert [i for i, _ in pure.served] == [0, 1]
    assert schedule_reward(problem, pure) == pytest.approx(3 * 0.94 ** 20 + 5 * 0.96 ** 80)
    considerate = run_planner(problem, RolloutPlanner())
    assert [i for i, _ in considerate.served] == [1, 0]
    assert schedule_reward(problem, considerate) == pytest.approx(5 * 0.96 ** 60 + 3 * 0.94 ** 80)
