"""Algorithm 4-2 decided at every step (thesis 000 §4.2.3): worked examples and Eq. 4-3."""
import itertools

import numpy as np
import pytest
from planner_factories import make_instruction

from task_planner.baselines import exhaustive_optimum
from task_planner.graph import floyd_warshall, graph_from_edges
from task_planner.problem import Problem, order_reward, schedule_reward, score_route
from task_planner.ripple_planner import RipplePlanner, ripple_field
from task_planner.robot_state import RobotState, step_adjacency
from task_planner.simulate import run_planner
from task_planner.step_planner import RippleField, StepRipplePlanner, per_step_decision

A, B, C = 0, 1, 2


def fig_4_8(with_cb=True):
    """Fig. 4-8: instructions on C, the robot on edge A-B; C-A k = 3, C-B l = 5, A-B 4 (1 step
    = 1 m). Without the C-B edge, l becomes 3 + 4 = 7 (the figure's 'edge l does not exist')."""
    edges = [("A", "B", 4.0), ("C", "A", 3.0)] + ([("C", "B", 5.0)] if with_cb else [])
    steps = step_adjacency(graph_from_edges("ABC", edges).adjacency, 1.0)
    return steps, floyd_warshall(steps)[0]


def decide(steps, shortest, state, gamma, beta, nodes):
    field = RippleField(shortest, 1.0)
    gamma, beta, nodes = np.array(gamma), np.array(beta), np.array(nodes)
    field.sync(np.arange(len(gamma)), gamma, beta, nodes)
    return per_step_decision(field, state, steps, gamma, beta, nodes)


@pytest.mark.parametrize("with_cb", [True, False])
def test_fig_4_8_candidate_steps_follow_eq_4_4(with_cb):
    steps, shortest = fig_4_8(with_cb)
    on_edge = RobotState(np.array([1, 3, 0]))  # a = 1 step to A, b = 3 steps to B
    n_hat, nxt, candidates, values = decide(steps, shortest, on_edge, [2.0], [0.9], [C])
    assert candidates.tolist() == [A, B]
    # L-1 is node A: t = k = 3. L+1 has a = 2, b = 2: t = min(k + a, l + b) = min(5, 7 or 9) = 5,
    # which without the C-B edge is the figure's l - b = 7 - 2
    assert values == pytest.approx([2 * 0.9 ** 3, 2 * 0.9 ** 5])
    assert n_hat == A and nxt.node == A


def test_fig_4_8_a_stronger_instruction_beyond_b_wins():
    steps, shortest = fig_4_8()
    on_edge = RobotState(np.array([1, 3, 0]))
    # (2, 0.9) on C as above and (8, 0.98) on B: toward A 2 * 0.9^3 + 8 * 0.98^4,
    # toward B 2 * 0.9^5 + 8 * 0.98^2
    n_hat, nxt, _, values = decide(steps, shortest, on_edge, [2.0, 8.0], [0.9, 0.98], [C, B])
    assert values == pytest.approx([2 * 0.9 ** 3 + 8 * 0.98 ** 4, 2 * 0.9 ** 5 + 8 * 0.98 ** 2])
    assert n_hat == B and nxt.vector.tolist() == [2, 2, 0] and nxt.node is None


def test_memorised_field_follows_arrivals_and_services(line_graph):
    steps = step_adjacency(line_graph.adjacency, 1.0)
    shortest = floyd_warshall(steps)[0]
    gamma, beta, node = np.array([2.0, 8.0, 5.0]), np.array([0.9, 0.98, 0.96]), np.array([0, 3, 1])
    field = RippleField(shortest, 1.0)
    for held in ([0], [0, 1], [0, 1, 2], [1, 2], [2], []):
        field.sync(np.array(held, dtype=int), gamma, beta, node)
        fresh = ripple_field(gamma[held], beta[held], node[held], shortest, 1.0) if held else 0.0
        assert field.values == pytest.approx(fresh, abs=1e-12)
        assert field.held() == held


def eq_4_3_problem(graph, count, c_s, gamma=3.0, beta=0.94):
    """Fig. 4-5: the same (gamma, beta) on every node but the start; no service time."""
    instructions = tuple(make_instruction(k, k, gamma, beta) for k in range(1, count + 1))
    return Problem(graph, instructions, speed_mps=1.0, start_node=0)


@pytest.mark.parametrize("shape", ["line", "ring"])
def test_eq_4_3_special_case_reaches_the_optimum(shape):
    count, c = 6, 2.0
    names = [str(k) for k in range(count + 1)]
    edges = [(names[k], names[k + 1], c) for k in range(count)]
    if shape == "ring":
        edges.append((names[count], names[0], c))
    problem = eq_4_3_problem(graph_from_edges(names, edges), count, c)
    schedule = run_planner(problem, StepRipplePlanner(step_s=1.0))
    r_opt = sum(3.0 * 0.94 ** (i * c) for i in range(1, count + 1))   # Eq. 4-3
    assert schedule_reward(problem, schedule) == pytest.approx(r_opt)
    assert order_reward(problem, exhaustive_optimum(problem, 10)) == pytest.approx(r_opt)


def test_an_arrival_turns_the_robot_back_mid_edge():
    # A -4- B. At t = 0 only (1, 0.9) on B; one step later (8, 0.9) launches on A. At (A:1, B:3):
    # back to A is worth 8 + 0.9^4 = 8.66, on toward B 8 * 0.9^2 + 0.9^2 = 7.29.
    graph = graph_from_edges("AB", [("A", "B", 4.0)])
    instructions = (make_instruction(1, B, 1.0, 0.9),
                    make_instruction(2, A, 8.0, 0.9, start_time=1.0))
    problem = Problem(graph, instructions, speed_mps=1.0, start_node=A)
    schedule = run_planner(problem, StepRipplePlanner(step_s=1.0))
    # two steps out and back are a 2 s wait on A; the repeated A costs no travel
    assert schedule.route == [A, A, B]
    assert schedule.waits == {0: 2.0}
    assert schedule.served == [(1, 1), (0, 2)]
    assert schedule.completion.tolist() == [2.0, 6.0]
    assert score_route(problem, schedule.route, schedule.served, schedule.waits).tolist() \
        == [2.0, 6.0]
    stepwise = schedule_reward(problem, schedule)
    assert stepwise == pytest.approx(8 * 0.9 ** 1 + 0.9 ** 6)
    # deciding once per node drives on to B first
    per_node = run_planner(problem, RipplePlanner(step_s=1.0))
    assert per_node.route == [A, B, A]
    assert schedule_reward(problem, per_node) == pytest.approx(0.9 ** 4 + 8 * 0.9 ** 7)
    assert stepwise > schedule_reward(problem, per_node)


def test_loop_guard_ends_the_out_and_back_at_a_peaked_hub(star_graph):
    # equal instructions on the three leaves (4 steps): the field peaks on the hub (3 * 0.9^4)
    # above one step out (0.9^3 + 2 * 0.9^5) and two steps out (0.9^2 + 2 * 0.9^6)
    instructions = tuple(make_instruction(k, k, 1.0, 0.9) for k in (1, 2, 3))
    problem = Problem(star_graph, instructions, speed_mps=1.0, start_node=0)
    planner = StepRipplePlanner(step_s=1.0)
    schedule = run_planner(problem, planner)
    assert planner.guard_activations >= 1
    assert sorted(i for i, _ in schedule.served) == [0, 1, 2]
    assert schedule.route[:2] == [0, 0]  # out one step and back before the guard took over


def test_step_planner_equals_per_node_planner_without_arrivals_or_loops(line_graph):
    rng = np.random.default_rng(7)
    for trial in range(20):
        instructions = tuple(make_instruction(k + 1, int(rng.integers(4)),
                                              float(rng.choice([8, 5, 3, 2, 1])),
                                              float(rng.choice([0.98, 0.96, 0.94, 0.92, 0.9])),
                                              int(rng.integers(1, 11))) for k in range(5))
        problem = Problem(line_graph, instructions, speed_mps=0.5, start_node=1)
        step, node = StepRipplePlanner(step_s=1.0), RipplePlanner(step_s=1.0)
        by_step, by_node = run_planner(problem, step), run_planner(problem, node)
        if step.guard_activations == 0 and node.guard_activations == 0:
            assert by_step.route == by_node.route and by_step.served == by_node.served


def test_serving_from_an_edge_is_refused(line_graph):
    class Rogue(StepRipplePlanner):
        def decide(self, state, clock, available):
            return ("serve", 0) if state.node is None else ("step", 2)

    problem = Problem(line_graph, (make_instruction(1, 2),), speed_mps=1.0, start_node=1)
    with pytest.raises(RuntimeError, match="from an edge"):
        run_planner(problem, Rogue())


def test_every_permutation_scores_no_better_than_the_step_planner_on_the_line(line_graph):
    # on a line with no arrivals the seed's rule is optimal for equal instructions (Eq. 4-3)
    instructions = tuple(make_instruction(k + 1, node, 2.0, 0.9)
                         for k, node in enumerate((0, 2, 3)))
    problem = Problem(line_graph, instructions, speed_mps=1.0, start_node=0)
    best = max(order_reward(problem, order) for order in itertools.permutations(range(3)))
    schedule = run_planner(problem, StepRipplePlanner(step_s=1.0))
    assert schedule_reward(problem, schedule) == pytest.approx(best)
