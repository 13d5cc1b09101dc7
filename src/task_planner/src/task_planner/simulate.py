"""Executes a planner on a problem, online: instructions appear at their launch times.

The three kinds of `planner_api` are run, told apart by the kind the planner states (`kind_of`):
- node planners (`decide(node, clock, available)` -> ('serve', i) or ('move', neighbour)) are asked
  again at every node, like the seed's planner decided per node;
- target planners (`choose(node, clock, available)` -> i) pick one instruction, the robot drives
  the shortest path to it and serves it, then the planner is asked again;
- step planners (`decide(state, clock, available)` -> ('serve', i) or ('step', neighbour)) are
  asked at every step of `step_s` seconds along the edges and may turn back mid-edge. The
  schedule keeps the same form: a leg from node to node is scored as its edge at the problem's
  speed, and the steps spent beyond that edge (turning back and forth) as a wait before leaving
  (the time is what counts); a leg that ends where it began repeats the node in the route.
`available` holds the indices of launched, pending instructions whose predecessor is done. Wall
time spent in the planner is measured per call (decision time).
"""
import time
from typing import Any, cast

import numpy as np

from task_planner.planner_api import NODE, STEP, NodePlanner, Planner, StepPlanner, \
    TargetPlanner, kind_of
from task_planner.problem import Problem, Schedule, score_route
from task_planner.robot_state import RobotState, state_transition


def run_planner(problem: Problem, planner: Planner) -> Schedule:
    """Run `planner` (a planner_api planner) to completion on `problem`; returns a scored
    Schedule."""
    kind = kind_of(planner)
    planner.reset(problem)
    run = _Run(problem)
    if kind == STEP:
        run.state = cast(StepPlanner, planner).start_state()
    while run.pending:
        available = run.available()
        if not len(available):
            run.wait_for_next_launch()
            continue
        started, started_cpu = time.perf_counter(), time.thread_time()
        action: str
        if kind == NODE:
            action, value = cast(NodePlanner, planner).decide(run.node, run.clock, available)
        elif kind == STEP:
            action, value = cast(StepPlanner, planner).decide(run.robot_state(), run.clock,
                                                              available)
        else:
            action, value = "target", cast(TargetPlanner, planner).choose(run.node, run.clock,
                                                                          available)
        run.decision_calls.append(time.perf_counter() - started)
        run.decision_cpu_calls.append(time.thread_time() - started_cpu)
        run.decision_s += run.decision_calls[-1]
        run.apply(action, value, planner)
    return run.finish()


class _Run:
    """Mutable execution state of one run."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        self.node, self.clock = problem.start_node, 0.0
        self.pending = set(range(problem.count))
        self.route: list[int] = [self.node]
        self.served: list[tuple[int, int]] = []
        self.waits: dict[int, float] = {}
        self.decision_before: list[float] = []
        self.decision_s = 0.0
        self.decision_calls: list[float] = []
        self.decision_cpu_calls: list[float] = []
        self.state: RobotState | None = None  # a step planner's robot_state.RobotState
        self.leg: list[Any] = []  # a step planner's leg: [from node, depart time [s], steps taken]

    def robot_state(self) -> RobotState:
        """A step planner's state; RuntimeError for a run that has none."""
        if self.state is None:
            raise RuntimeError("a step planner's run has no robot state")
        return self.state

    def available(self) -> np.ndarray:
        p = self.problem
        return np.array(sorted(i for i in self.pending if p.launch[i] <= self.clock
                               and (p.predecessor[i] < 0 or p.predecessor[i] not in self.pending)),
                        dtype=int)

    def wait_for_next_launch(self) -> None:
        p = self.problem
        self.clock = min(p.launch[i] for i in self.pending if p.launch[i] > self.clock) \
            if any(p.launch[i] > self.clock for i in self.pending) else self._stuck()
        self.waits[len(self.route) - 1] = self.clock

    def _stuck(self) -> float:
        raise RuntimeError("pending instructions can never become available")

    def apply(self, action: str, value: int, planner: Planner) -> None:
        if action == "serve":
            self._serve(value)
        elif action == "move":
            self._move(value)
        elif action == "step":
            self._step(value, cast(StepPlanner, planner))
        else:  # a target planner's choice: drive there, then serve
            for node in self.problem.graph.path(self.node, int(self.problem.node[value]))[1:]:
                self._move(node)
            self._serve(value)

    def _move(self, neighbour: int) -> None:
        length_s = self.problem.edge_s[self.node, neighbour]
        if length_s <= 0:
            raise RuntimeError(f"planner moved from node {self.node} to non-neighbour {neighbour}")
        self.clock += length_s
        self.node = int(neighbour)
        self.route.append(self.node)

    def _step(self, neighbour: int, planner: StepPlanner) -> None:
        """One step of a step planner; arriving on a node closes the leg (module docstring)."""
        if self.robot_state().node is not None:
            self.leg = [self.node, self.clock, 0]
        self.state = state_transition(planner.step_adj, self.robot_state(), int(neighbour))
        self.leg[2] += 1
        self.clock += planner.step_s
        if self.state.node is None:
            return
        start, depart, steps = self.leg
        end = self.state.node
        direct = planner.step_adj[start, end] if end != start else 0
        extra_s = (steps - direct) * planner.step_s
        if extra_s > 0:
            self.waits[len(self.route) - 1] = depart + extra_s
        self.clock = depart + extra_s + (self.problem.edge_s[start, end] if end != start else 0.0)
        self.node = int(end)
        self.route.append(self.node)

    def _serve(self, index: int) -> None:
        p = self.problem
        if self.state is not None and self.state.node is None:
            raise RuntimeError(f"planner served instruction {index} from an edge")
        if index not in self.pending or p.node[index] != self.node:
            raise RuntimeError(f"planner served instruction {index} away from its node or twice")
        self.clock = max(self.clock, p.launch[index]) + p.duration[index]
        self.pending.discard(index)
        self.served.append((int(index), len(self.route) - 1))
        self.decision_before.append(self.decision_s)

    def finish(self) -> Schedule:
        schedule = Schedule(route=self.route, served=self.served, waits=self.waits,
                            decision_before=self.decision_before, decision_s=self.decision_s,
                            decision_calls=self.decision_calls,
                            decision_cpu_calls=self.decision_cpu_calls)
        schedule.completion = score_route(self.problem, self.route, self.served, self.waits)
        return schedule
