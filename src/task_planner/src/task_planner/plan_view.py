"""What the executor shows of its reasoning (ROS-free): the reward ripple over the graph, the next
node it heads for and the plan it would follow if nothing new arrived.

`ros_markers.py` turns a `PlanView` into rviz markers.
"""
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from task_planner.graph import TopologicalGraph, floyd_warshall
from task_planner.instruction import Instruction
from task_planner.planner_api import Planner
from task_planner.problem import Problem
from task_planner.ripple_planner import ripple_field
from task_planner.robot_state import step_adjacency
from task_planner.simulate import run_planner


@dataclass(frozen=True)
class PlanView:
    values: np.ndarray     # (V,) expected reward per graph node, Fig. 4-6
    robot_node: int        # node the robot is on or last left
    next_node: int         # node the robot heads for (-1 when idle or executing)
    route: tuple           # planned node sequence from robot_node (empty when nothing is open)
    stops: tuple           # ((instruction id, node), ...) in planned service order


def ripple_values(graph: TopologicalGraph, instructions: Sequence[Instruction], speed_mps: float,
                  step_s: float) -> np.ndarray:
    """Fig. 4-6: expected reward on each node, sum_i gamma_i * beta_i ** (steps(m_i, n) * step_s).

    Steps are the seed's edge discretisation (edges cut into `speed_mps * step_s` metre steps,
    the same as `RipplePlanner`); no instruction gives zeros.
    """
    if not instructions:
        return np.zeros(graph.size)
    shortest_steps = floyd_warshall(step_adjacency(graph.adjacency, speed_mps * step_s))[0]
    gamma = np.array([i.gamma for i in instructions], dtype=float)
    beta = np.array([i.beta for i in instructions], dtype=float)
    nodes = np.array([i.destination for i in instructions], dtype=int)
    return ripple_field(gamma, beta, nodes, shortest_steps, step_s)


def planned_order(graph: TopologicalGraph, instructions: Sequence[Instruction], planner: Planner,
                  speed_mps: float, start_node: int
                  ) -> tuple[tuple[int, ...], tuple[tuple[int, int], ...]]:
    """The route and service order `planner` would follow on the open `instructions`.

    All are taken as launched now (t = 0); chains (`previous_id`) hold. Returns (route, stops)
    with stops = ((instruction id, node), ...).
    """
    if not instructions:
        return (), ()
    launched = tuple(replace(i, start_time=0.0) for i in instructions)
    problem = Problem(graph, launched, speed_mps, start_node)
    schedule = run_planner(problem, planner)
    stops = tuple((int(problem.ids[index]), int(problem.node[index]))
                  for index, _ in schedule.served)
    return tuple(int(n) for n in schedule.route), stops


def plan_view(graph: TopologicalGraph, instructions: Sequence[Instruction], planner: Planner,
              speed_mps: float, step_s: float, robot_node: int, next_node: int,
              plan_max: int | None = None) -> PlanView:
    """The `PlanView` of the open (pending) instructions for a robot at `robot_node`.

    With more than `plan_max` instructions the plan is left empty (playing a planner forward over
    a flood would cost more than a decision); the ripple values are always computed.
    """
    route: tuple[int, ...] = ()
    stops: tuple[tuple[int, int], ...] = ()
    if plan_max is None or len(instructions) <= plan_max:
        route, stops = planned_order(graph, instructions, planner, speed_mps, robot_node)
    return PlanView(values=ripple_values(graph, instructions, speed_mps, step_s),
                    robot_node=int(robot_node), next_node=int(next_node), route=route,
                    stops=stops)
