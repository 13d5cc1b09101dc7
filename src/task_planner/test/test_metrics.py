import pytest
from planner_factories import make_instruction

from task_planner.metrics import (average_index, completion_time, navigation_time,
                                  order_by_average_index, reward_curve, similarity_cost,
                                  time_ratio)
from task_planner.problem import Problem, order_to_schedule


def test_eq_5_1_seed_example():
    assert similarity_cost([2, 4, 3, 1], [1, 2, 3, 4]) == 6


def test_eq_5_1_reproduces_table_5_8_costs():
    opt = [1, 2, 8, 6, 10, 9, 7, 3, 5, 4]
    table = {(1, 2, 3, 4, 5, 6, 7, 8, 9, 10): 30, (9, 1, 4, 7, 5, 2, 3, 10, 8, 6): 40,
             (2, 10, 8, 1, 6, 9, 5, 3, 4, 7): 14, (1, 4, 3, 5, 6, 8, 9, 7, 10, 2): 36,
             (2, 1, 10, 8, 6, 7, 9, 5, 3, 4): 10}
    for order, cost in table.items():
        assert similarity_cost(list(order), opt) == cost
    # Table 5-10: human order vs optimal order, cost 2
    assert similarity_cost([1, 2, 6, 8, 10, 9, 7, 3, 5, 4], opt) == 2


def test_eq_5_1_rejects_different_sets():
    with pytest.raises(ValueError, match="different instructions"):
        similarity_cost([1, 2], [1, 3])


def test_eq_5_3_seed_example():
    samples = [[2, 4, 3, 1], [1, 2, 3, 4], [3, 2, 1, 4]]
    means = average_index(samples)
    assert [round(means[i], 2) for i in (1, 2, 3, 4)] == [2.67, 1.67, 2.33, 3.33]
    assert order_by_average_index(samples) == [2, 3, 1, 4]


def test_eq_5_2_time_ratio():
    assert time_ratio(30.0, 2.0, 8.0) == pytest.approx(0.75)
    assert time_ratio(0.0, 0.0, 0.0) == 0.0


def test_curve_completion_and_navigation(line_graph):
    instructions = (make_instruction(1, 3, 3.0, 0.5, 2), make_instruction(2, 0, 1.0, 0.5, 1))
    problem = Problem(line_graph, instructions, speed_mps=1.0, start_node=1)
    schedule = order_to_schedule(problem, [1, 0])   # A done at 1+1 = 2 s, D at 2+6+2 = 10 s
    times, accumulated = reward_curve(problem, schedule)
    assert times.tolist() == [2.0, 10.0]
    assert accumulated == pytest.approx([0.25, 0.25 + 3 * 0.5 ** 10])
    assert completion_time(schedule) == 10.0
    assert navigation_time(problem, schedule) == 7.0
