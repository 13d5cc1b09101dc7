"""An in-process navigation model that runs the Executor without ROS (tests, benchmarks, demo).

Time model as task_planner.problem: the robot drives graph edges at `speed_mps`; a goal on an edge
listed in `blocked` is aborted `abort_after_s` after it was sent (move_base finding no path); a
robot function takes its `Execute.duration_s`. Turning back mid-edge costs the time already driven
on that edge. Instructions arrive at their given times.
"""
from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, TypedDict

from task_planner.executor_commands import (Ask, Command, Execute, Navigate, Say, StopMotion,
                                            Verify, Wait)
from task_planner.graph import TopologicalGraph
from task_planner.instruction import Instruction

if TYPE_CHECKING:   # executor imports the behaviours, which need not load for the model
    from task_planner.executor import Executor


@dataclass
class NavigationModel:
    graph: TopologicalGraph
    speed_mps: float = 0.5         # driving speed [m/s]
    blocked: set[frozenset[int]] = field(default_factory=set)  # edges that cannot be driven
    abort_after_s: float = 2.0     # time move_base takes to give up on a blocked goal [s]
    turn_s: float = 2.0            # time one turn of a look around takes [s]


@dataclass
class Trace:
    """What happened in a run: goals sent, functions executed, sentences spoken."""

    goals: list[tuple[float, int]] = field(default_factory=list)       # (time [s], node)
    executed: list[tuple[float, int, str]] = field(default_factory=list)  # (time [s],
                                                    # instruction id, function name)
    said: list[tuple[float, str]] = field(default_factory=list)        # (time [s], text)


class _Drive:
    """The goal being driven to: from `origin` to `goal`, arriving (or aborting) at `eta`."""

    def __init__(self, origin: int, goal: int, eta: float, edge_s: float, aborts: bool) -> None:
        self.origin, self.goal, self.eta, self.edge_s, self.aborts = (origin, goal, eta, edge_s,
                                                                      aborts)


class _Model(TypedDict):
    """One robot's state in the model: the drive under way and when its function ends."""

    drive: _Drive | None
    execution_end: float | None


def run_executor(executor: Executor, arrivals: Iterable[tuple[float, Instruction]],
                 navigation: NavigationModel, until_s: float = float("inf"),
                 start_s: float = 0.0) -> Trace:
    """Run `executor` from `start_s` on `arrivals` [(time [s], Instruction)] until `until_s`.

    Returns the Trace; results are in executor.buffer.
    """
    pending = sorted(arrivals, key=lambda item: item[0])
    trace, state = Trace(), _Model(drive=None, execution_end=None)

    def carry_out(commands: Iterable[Command], clock: float) -> None:
        _carry_out(commands, clock, executor, navigation, state, trace)

    clock = start_s
    carry_out(executor.tick(clock), clock)
    while True:
        drive, end = state["drive"], state["execution_end"]
        times = [t for t in (pending[0][0] if pending else None,
                             drive.eta if drive else None, end) if t is not None]
        if not times or min(times) > until_s:
            return trace
        clock = max(clock, min(times))
        if pending and pending[0][0] <= clock:
            batch = []
            while pending and pending[0][0] <= clock:
                batch.append(pending.pop(0)[1])
            carry_out(executor.receive(batch, clock)[1], clock)
        elif drive is not None and drive.eta <= clock:
            state["drive"] = None
            commands = (executor.aborted(clock, "no path to the goal") if drive.aborts
                        else executor.arrived(clock))
            carry_out(commands, clock)
        else:
            state["execution_end"] = None
            carry_out(executor.tick(clock), clock)


def _carry_out(commands: Iterable[Command], clock: float, executor: Executor,
               navigation: NavigationModel, state: _Model, trace: Trace) -> None:
    """Start what the executor's commands ask for in the model; note them in the trace."""
    for command in commands:
        if isinstance(command, Navigate) and command.yaw is not None:  # turn in place
            state["drive"] = _Drive(command.node, command.node, clock + navigation.turn_s,
                                    0.0, False)
        elif isinstance(command, Navigate):
            state["drive"] = _start_drive(navigation, state["drive"], executor.node,
                                          command.node, clock)
            trace.goals.append((clock, command.node))
        elif isinstance(command, StopMotion):
            state["drive"] = None
        elif isinstance(command, Execute):
            state["execution_end"] = clock + command.duration_s
            trace.executed.append((clock, command.instruction_id, command.function))
        elif isinstance(command, (Verify, Wait)):   # wake up when the wait is over
            state["execution_end"] = command.until_s
        elif isinstance(command, Say):
            trace.said.append((clock, command.text))
        elif isinstance(command, Ask):   # nobody answers in the model: the look goes on
            trace.said.append((clock, f"{command.name}, are you here?" if command.call else
                               f"Excuse me, are you {command.name}?"))


def _start_drive(navigation: NavigationModel, current: _Drive | None, node: int, goal: int,
                 clock: float) -> _Drive:
    """A new drive toward `goal`: a turn back mid-edge, a retry, or leaving node `node`."""
    if current is not None and goal == current.origin:  # turn back: retrace what was driven
        driven_s = current.edge_s - (current.eta - clock)
        return _Drive(current.goal, goal, clock + driven_s, current.edge_s, False)
    origin = node if current is None else current.origin
    length_m = navigation.graph.adjacency[origin, goal]
    if length_m <= 0:
        raise RuntimeError(f"navigation goal {goal} is not a neighbour of node {origin}")
    edge_s = length_m / navigation.speed_mps
    if frozenset((origin, goal)) in navigation.blocked:
        return _Drive(origin, goal, clock + navigation.abort_after_s, edge_s, True)
    return _Drive(origin, goal, clock + edge_s, edge_s, False)


def run_executor_fleet(executors: Sequence[Executor],
                       arrivals: Iterable[tuple[float, int, Instruction]],
                       navigation: NavigationModel, step_s: float = 0.25, until_s: float = 3600.0,
                       kills: Iterable[tuple[float, int]] = ()) -> list[Trace]:
    """Run the executors of a fleet (each with its FleetLink on one pool) side by side.

    `arrivals`: [(time [s], robot index, Instruction)], each submitted to that robot; `kills`:
    [(time [s], robot index)], from when that robot's executor is gone (it stops where it is,
    holding what it held; what would arrive to it later is lost with the sender's request). Time
    advances in steps of `step_s`, the executors' tick period: a robot learns what the others shared
    or closed at its next tick. Runs until nothing is open in a live robot's journal and nothing is
    left to arrive, or until `until_s`. Returns one Trace per robot.
    """
    pending = sorted(arrivals, key=lambda item: item[0])
    killed = dict((robot, t) for t, robot in kills)
    traces = [Trace() for _ in executors]
    states = [_Model(drive=None, execution_end=None) for _ in executors]
    clock = 0.0
    while clock <= until_s:
        live = [k for k in range(len(executors)) if clock < killed.get(k, float("inf"))]
        for k in live:
            executor, state, trace = executors[k], states[k], traces[k]
            commands: list[Command] = []
            batch = [i for t, robot, i in pending if t <= clock and robot == k]
            if batch:
                commands += executor.receive(batch, clock)[1]
            drive = state["drive"]
            if drive is not None and drive.eta <= clock:
                state["drive"] = None
                commands += (executor.aborted(clock, "no path to the goal") if drive.aborts
                             else executor.arrived(clock))
            end = state["execution_end"]
            if end is not None and end <= clock:
                state["execution_end"] = None
            _carry_out(commands + executor.tick(clock), clock, executor, navigation, state,
                       trace)
        pending = [a for a in pending if a[0] > clock]   # a gone robot's are never taken
        if not pending and all(not executors[k].buffer.open_records() for k in live):
            return traces
        clock += step_s
    return traces
