"""task_planner.fleet_waiting: idle robots of a fleet wait at the graph's k-median places."""
import pytest
from planner_factories import make_instruction

from task_planner import fleet_waiting
from task_planner.fleet import RobotStart, run_fleet
from task_planner.fleet_registry import make_allocator
from task_planner.fleet_waiting import waiting_place_of, waiting_places
from task_planner.problem import Problem

A, B, C, D = range(4)


def test_the_k_median_of_a_line_by_hand(line_graph):
    """A -1- B -2- C -3- D: from {B, D} a node is 0.75 m away on average (A 1, B 0, C 2, D 0),
    the least of every pair; alone, B and C tie at 2 m and the first wins; without B, {A, C}
    and {A, D} tie at 1 m."""
    travel = line_graph.shortest
    assert waiting_places(travel, 2) == (B, D)
    assert waiting_places(travel, 1) == (B,)
    assert waiting_places(travel, 2, candidates=[A, C, D]) == (A, C)
    assert waiting_places(travel, 4) == (A, B, C, D)
    with pytest.raises(ValueError, match="need at least one"):
        waiting_places(travel, 0)


def test_greedy_and_swaps_find_the_exact_median_where_enumeration_is_too_big(line_graph,
                                                                            monkeypatch):
    monkeypatch.setattr(fleet_waiting, "EXACT_SETS", 0)
    assert waiting_places(line_graph.shortest, 2) == (B, D)


def test_idle_robots_are_matched_to_the_places_by_least_travel(line_graph):
    travel = line_graph.shortest
    assert waiting_place_of(0, [A, D], [0, 1], (B, D), travel) == B
    assert waiting_place_of(1, [A, D], [0, 1], (B, D), travel) == D
    assert waiting_place_of(0, [D, A], [0, 1], (B, D), travel) == D
    assert waiting_place_of(1, [A, D], [0], (B, D), travel) is None      # busy


def test_a_robot_waiting_at_a_median_serves_a_late_instruction_sooner(line_graph):
    """Both robots start on A; one instruction there at 0 s, one on D at 100 s. The auction's
    robots wait on A, 12 s from D at 0.5 m/s; with waiting places one robot waits on D."""
    problem = Problem(line_graph, (make_instruction(1, A, duration=1),
                                   make_instruction(2, D, duration=1, start_time=100.0)), 0.5, A)
    starts = [RobotStart(A)] * 2
    plain = run_fleet(problem, starts, make_allocator("auction"))
    waiting = run_fleet(problem, starts, make_allocator("auction_waiting"))
    assert plain.completion[1] == pytest.approx(113.0)
    assert waiting.completion[1] == pytest.approx(101.0)
    assert sorted(i for order in waiting.orders for i in order) == [0, 1]


def test_the_online_ceiling_by_hand(line_graph):
    """One robot, beta 0.5 per second of travel: from B a node is 1, 0, 2 or 5 s away, so it
    earns (0.5 + 1 + 0.25 + 0.5 ** 5) / 4 = 0.4453 of a robot waiting there, the best node;
    with a robot on every node nothing is lost."""
    from task_planner.fleet_waiting import online_ceiling
    assert online_ceiling(line_graph.shortest, 1, [(1.0, 0.5)], [0.0]) == pytest.approx(
        (0.5 + 1 + 0.25 + 0.5 ** 5) / 4)
    assert online_ceiling(line_graph.shortest, 4, [(8.0, 0.98), (1.0, 0.9)], [1, 10]) == 1.0
