"""The TAMP executor of thesis 000 §4.2.5 (Fig. 4-14), ROS-free, as a behaviour tree.

Instruction cycle: perceptions are written into the task buffer; the executor *fetches* the open
instructions, *decodes* them into a planning problem, asks the configured planner for a
*decision*, hands the next neighbouring node to the motion planner as a navigation goal
(*execute*), and on completion *writes back* to the task buffer.

The executor never waits: its inputs are events with the current time (`receive`, `arrived`,
`aborted`, `tick`, `cancel`, `fault`) and its outputs are commands (`Navigate`, `Execute`, `Say`,
...) for the node (move_base, /robot/say) or an in-process model to carry out. Each event ticks
the behaviour tree of task_planner.behaviours.tree once; the behaviours (serve, look around,
search, patrol, give way, ask to pass and retry, charge, fleet claims and corridors) are the
modules of task_planner.behaviours, and the planner stays a ROS-free decision they ask.
"""
from collections import deque
from collections.abc import Iterable, Sequence

import numpy as np

from task_planner.behaviours.accounting import activity
from task_planner.behaviours.charging import BATTERY_KEY, save_battery
from task_planner.behaviours.context import (ABORTED, ARRIVED, CANCELLED, RECEIVED, TICK,
                                             OVERDUE_ORDERS, Charging, Context,
                                             ExecutorConfig)
from task_planner.behaviours.fleet_allocation import fleet_allocator
from task_planner.behaviours.looking import not_answered
from task_planner.behaviours.receiving import new_id
from task_planner.behaviours.recovery import fault
from task_planner.behaviours.tree import build_tree, drawing, tick
from task_planner.executor_commands import Command
from task_planner.fleet_link import FleetLink
from task_planner.graph import TopologicalGraph
from task_planner.instruction import Instruction
from task_planner.people_belief import PeopleAtPlaces
from task_planner.planner_api import NODE, STEP, Planner, kind_of
from task_planner.robot_functions import RobotFunction
from task_planner.task_buffer import Record, TaskBuffer

__all__ = ["OVERDUE_ORDERS", "Charging", "Executor", "ExecutorConfig", "latency_ms",
           "nearest_node"]


def latency_ms(samples_s: Sequence[float]) -> tuple[float, float, float]:
    """(median, 95th percentile, max) [ms] of wall times [s]; zeros when there are none."""
    if not len(samples_s):
        return 0.0, 0.0, 0.0
    ms = 1000.0 * np.asarray(samples_s, dtype=float)
    return float(np.median(ms)), float(np.percentile(ms, 95)), float(ms.max())


def nearest_node(graph: TopologicalGraph, x: float, y: float) -> int:
    """The graph node whose pose is closest to (x, y) [m]: where a restarted robot stands."""
    poses = np.asarray(graph.poses, dtype=float)  # (V, 3) x, y, yaw [m, m, rad]
    return int(np.argmin(np.hypot(poses[:, 0] - x, poses[:, 1] - y)))


class Executor:
    """Fetch → decode → decide → navigate → verify → execute → write back (Fig. 4-14).

    `state` is the behaviours' shared Context; `mode`, `node`, `goal`, `log`, the decision
    times and the collaborators are read through it.
    """

    def __init__(self, buffer: TaskBuffer, graph: TopologicalGraph, planner: Planner,
                 people: PeopleAtPlaces, functions: dict[int, RobotFunction],
                 config: ExecutorConfig | None = None, start_node: int = 0,
                 charging: Charging | None = None, fleet: FleetLink | None = None) -> None:
        if kind_of(planner) == STEP:
            raise ValueError(f"planner {planner.name!r} decides every step along an edge; the "
                             f"executor drives whole edges and runs node or target planners")
        config = config or ExecutorConfig()
        self.state = Context(buffer, graph, planner, people, functions, config,
                             node=int(start_node), node_planner=kind_of(planner) == NODE,
                             charging=charging, fleet=fleet,
                             decision_s=deque(maxlen=config.latency_window),
                             decision_cpu_s=deque(maxlen=config.latency_window))
        self.tree = build_tree(self.state)
        fleet_allocator(self.state)      # an unknown config.fleet_allocator is refused here
        if charging is not None:         # a restarted executor resumes the journalled level
            battery = charging.battery
            battery.level_wh = min(battery.config.capacity_wh,
                                   buffer.robot_value(BATTERY_KEY, battery.level_wh))
            save_battery(self.state, force=True)

    # ---- events: each ticks the tree once and returns its commands ----

    def receive(self, instructions: Iterable[Instruction],
                now: float) -> tuple[list[tuple[Record | None, str]], list[Command]]:
        """Journal new instructions (one transaction), share them with the fleet and re-decide;
        returns (results, commands)."""
        commands = tick(self.tree, self.state, RECEIVED, now, inbox=list(instructions),
                        results=[])
        return self.state.results, commands

    def tick(self, now: float) -> list[Command]:
        """Periodic step: finish an execution whose time is up, look, retry, or decide."""
        return tick(self.tree, self.state, TICK, now)

    def arrived(self, now: float) -> list[Command]:
        """The navigation goal was reached (or, while looking around, the heading)."""
        return tick(self.tree, self.state, ARRIVED, now)

    def aborted(self, now: float, reason: str) -> list[Command]:
        """Navigation gave up on the goal: ask to pass and retry, or fail and decide again."""
        return tick(self.tree, self.state, ABORTED, now, reason=reason)

    def cancel(self, instruction_id: int, now: float) -> tuple[Record, list[Command]]:
        """Withdraw an instruction (for the whole fleet); the robot stops its function if it was
        executing it. Returns (record, commands); an unknown id raises TaskBufferError."""
        record = self.state.buffer.get(instruction_id)   # an unknown id: refused before anything
        commands = tick(self.tree, self.state, CANCELLED, now, cancelled=record)
        return self.state.buffer.get(instruction_id), commands

    def fault(self, now: float, reason: str, fail: bool = True,
              rejoin: bool = False) -> list[Command]:
        """A step of the executor raised: fail the instruction being served with `reason` (with
        `fail` off, leave it open: another robot holds it, or the pool is out of reach), stop,
        and go idle; with `rejoin`, rejoin the fleet at the next event."""
        return fault(self.state, now, reason, fail_it=fail, rejoin=rejoin)

    def function_over(self, instruction_id: int, now: float) -> bool:
        """The robot function of `instruction_id` ended before its time was up (an introduce
        dialogue that is over): the next tick finishes it. False when the robot is not
        executing that instruction."""
        ctx = self.state
        if ctx.executing is None or ctx.executing[0] != instruction_id:
            return False
        ctx.executing = (instruction_id, min(ctx.executing[1], now))
        ctx.log.append((now, f"function of {instruction_id} over early"))
        return True

    def not_answered(self, name: str, place: str, now: float) -> bool:
        """The person asked at `place` whether they are `name` said no, or nobody answered:
        the look stops waiting for a yes (looking.ask_who). False when the robot is not
        waiting for that answer."""
        return not_answered(self.state, name, place, now)

    def new_id(self, previous_id: int = 0) -> int:
        """The id for an instruction whose sender lets the robot choose (its fleet's, if any)."""
        return new_id(self.state, previous_id)

    def serving(self) -> int:
        """Id of the instruction the robot serves (0 when idle or patrolling)."""
        return self.state.serving()

    def activity(self) -> str:
        """What the robot does now (behaviours.accounting: travel, look around, searching, ...)."""
        return activity(self.state)

    def drawing(self) -> str:
        """The behaviour tree with each node's status of the last event (text)."""
        return drawing(self.tree)

    # ---- what the robot's users read ----

    @property
    def node(self) -> int:
        return self.state.node

    @node.setter
    def node(self, node: int) -> None:   # where a restarted robot stands (nearest_node)
        self.state.node = int(node)

    mode = property(lambda self: self.state.mode)
    goal = property(lambda self: self.state.goal)
    log = property(lambda self: self.state.log)
    buffer = property(lambda self: self.state.buffer)
    fleet = property(lambda self: self.state.fleet)
    charging = property(lambda self: self.state.charging)
    decision_s = property(lambda self: self.state.decision_s)
    decision_cpu_s = property(lambda self: self.state.decision_cpu_s)
