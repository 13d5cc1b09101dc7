import numpy as np
import pytest
from planner_factories import make_instruction

from task_planner.baselines import (FirstComeFirstServe, PlannedOrder, PlannerTooLarge,
                                    PriorityFirst, RandomOrder, ShortestTimeFirst,
                                    exhaustive_optimum)
from task_planner.exact import exact_optimum
from task_planner.graph import graph_from_edges
from task_planner.instruction import InvalidInstruction
from task_planner.problem import Problem, order_reward, respects_chains
from task_planner.rollout_planner import RolloutPlanner
from task_planner.simulate import run_planner


@pytest.fixture
def problem(line_graph):
    # on A -1- B -2- C -3- D, robot on B, speed 1 m/s
    instructions = (make_instruction(1, 3, 3.0, 0.94, 2),    # D
                    make_instruction(2, 0, 1.0, 0.90, 1),    # A
                    make_instruction(3, 2, 8.0, 0.98, 5))    # C
    return Problem(line_graph, instructions, speed_mps=1.0, start_node=1)


def served_ids(problem, planner):
    return [int(problem.ids[i]) for i, _ in run_planner(problem, planner).served]


def test_dispatch_rules(problem):
    assert served_ids(problem, FirstComeFirstServe()) == [1, 2, 3]
    assert served_ids(problem, PriorityFirst()) == [3, 1, 2]
    # SF from B: D 5+2=7, A 1+1=2, C 2+5=7 -> A; from A: D 6+2, C 3+5 -> tie, lower id D
    assert served_ids(problem, ShortestTimeFirst()) == [2, 1, 3]
    assert sorted(served_ids(problem, RandomOrder(seed=3))) == [1, 2, 3]


def test_opt_by_hand(problem):
    # hand check of two orders: C, D, A: C done 2+5=7, D 7+3+2=12, A 12+6+1=19
    expected = 8 * 0.98 ** 7 + 3 * 0.94 ** 12 + 1 * 0.9 ** 19
    assert order_reward(problem, [2, 0, 1]) == pytest.approx(expected)
    best = exhaustive_optimum(problem)
    assert order_reward(problem, best) == pytest.approx(
        max(order_reward(problem, o) for o in
            ([0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0])))


def test_opt_refuses_large_sets_with_a_clear_message(line_graph):
    instructions = tuple(make_instruction(k, k % 4) for k in range(1, 12))
    problem = Problem(line_graph, instructions)
    with pytest.raises(PlannerTooLarge, match="11 instructions exceed the exhaustive limit of 10"):
        exhaustive_optimum(problem, max_instructions=10)


def random_problem(rng, graph, count, chains=False):
    priorities = [(8, .98), (5, .96), (3, .94), (2, .92), (1, .90)]
    instructions = []
    for k in range(1, count + 1):
        gamma, beta = priorities[rng.integers(5)]
        previous = int(rng.integers(1, k)) if chains and k > 1 and rng.random() < 0.3 else 0
        instructions.append(make_instruction(k, int(rng.integers(graph.size)), gamma, beta,
                                             int(rng.integers(0, 11)), previous_id=previous))
    start = int(rng.integers(graph.size))
    return Problem(graph, tuple(instructions), speed_mps=0.5, start_node=start)


@pytest.fixture
def home_graph():
    """A 7-place graph shaped like maps/household.graph.yaml (lengths in metres)."""
    return graph_from_edges(range(7), [(0, 1, 3.6), (1, 2, 5.5), (1, 4, 3.1), (1, 5, 4.5),
                                       (1, 6, 4.0), (2, 3, 3.0)])


def test_exact_equals_opt_on_200_random_sets(home_graph):
    rng = np.random.default_rng(2024)
    for trial in range(200):
        problem = random_problem(rng, home_graph, int(rng.integers(1, 9)), chains=trial % 2 == 1)
        opt, exact = exhaustive_optimum(problem), exact_optimum(problem)
        assert respects_chains(problem, exact)
        assert order_reward(problem, exact) == pytest.approx(order_reward(problem, opt), rel=1e-9)


def test_chained_instruction_waits_for_its_predecessor(line_graph):
    # 2 on A must follow 1 on D although A is next to the robot
    instructions = (make_instruction(1, 3, 1.0, 0.9), make_instruction(2, 0, 8.0, 0.98,
                                                                        previous_id=1))
    problem = Problem(line_graph, instructions, speed_mps=1.0, start_node=1)
    for planner in (FirstComeFirstServe(), PriorityFirst(), ShortestTimeFirst(),
                    RolloutPlanner(), PlannedOrder("Exact", exact_optimum)):
        assert served_ids(problem, planner) == [1, 2], planner.name
    assert exact_optimum(problem) == [0, 1]


def test_unknown_node_is_named(line_graph):
    with pytest.raises(InvalidInstruction,
                       match="instruction 1: destination node 9 is not in the graph"):
        Problem(line_graph, (make_instruction(1, 9),))


def test_previous_id_cycle_is_named(line_graph):
    instructions = (make_instruction(1, 0, previous_id=3), make_instruction(2, 1, previous_id=1),
                    make_instruction(3, 2, previous_id=2))
    with pytest.raises(InvalidInstruction, match="cycle: 1 -> 3 -> 2 -> 1"):
        Problem(line_graph, instructions)


def test_duplicate_id_is_named(line_graph):
    with pytest.raises(InvalidInstruction, match="instruction 4: duplicate id"):
        Problem(line_graph, (make_instruction(4, 0), make_instruction(4, 1)))
