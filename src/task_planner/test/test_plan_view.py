"""The executor's view: ripple values per node (Fig. 4-6), planned route and service order."""
import numpy as np
import pytest
from planner_factories import make_instruction

from task_planner.baselines import FirstComeFirstServe
from task_planner.plan_view import plan_view, planned_order, ripple_values
from task_planner.ripple_planner import RipplePlanner


def test_ripple_values_by_hand(line_graph):
    # A -1- B -2- C -3- D at 1 m/s, 1 s steps: gamma 2, beta 0.5 on B -> 2 * 0.5^[1, 0, 2, 5]
    # plus gamma 8, beta 0.9 on D -> 8 * 0.9^[6, 5, 3, 0]
    instructions = (make_instruction(1, 1, 2.0, 0.5), make_instruction(2, 3, 8.0, 0.9))
    values = ripple_values(line_graph, instructions, speed_mps=1.0, step_s=1.0)
    expected = [2 * 0.5 + 8 * 0.9 ** 6, 2.0 + 8 * 0.9 ** 5, 2 * 0.25 + 8 * 0.729,
                2 * 0.5 ** 5 + 8.0]
    assert values == pytest.approx(expected)
    assert ripple_values(line_graph, (), 1.0, 1.0).tolist() == [0.0] * 4


def test_planned_order_follows_the_planner_and_chains(line_graph):
    # FCFS in id order from B: 3 at A first (its predecessor-free), then 1 on D, then 2 (after 1)
    instructions = (make_instruction(3, 0), make_instruction(1, 3),
                    make_instruction(2, 2, previous_id=1))
    route, stops = planned_order(line_graph, instructions, FirstComeFirstServe(), 1.0, 1)
    assert stops == ((1, 3), (2, 2), (3, 0))
    assert route == (1, 2, 3, 2, 1, 0)


def test_plan_view_of_the_seed_planner(line_graph):
    instructions = (make_instruction(1, 0, 2.0, 0.9, 1), make_instruction(2, 3, 8.0, 0.98, 2))
    view = plan_view(line_graph, instructions, RipplePlanner(1.0), 1.0, 1.0, robot_node=1,
                     next_node=0)
    # same route as test_ripple_planner's run from B: A first, then D
    assert view.route == (1, 0, 1, 2, 3)
    assert view.stops == ((1, 0), (2, 3))
    assert (view.robot_node, view.next_node) == (1, 0)
    # A: 2 + 8 * 0.98^6 (D is 6 steps away), the field's peak
    assert view.values[0] == pytest.approx(2 + 8 * 0.98 ** 6)
    assert int(np.argmax(view.values)) == 0


def test_plan_left_out_beyond_plan_max(line_graph):
    instructions = (make_instruction(1, 1, 2.0, 0.5), make_instruction(2, 3, 8.0, 0.9))
    view = plan_view(line_graph, instructions, FirstComeFirstServe(), 1.0, 1.0, robot_node=0,
                     next_node=-1, plan_max=1)
    assert (view.route, view.stops) == ((), ())
    assert view.values[1] == pytest.approx(2.0 + 8 * 0.9 ** 5)
