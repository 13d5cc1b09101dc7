"""Several robots serving one instruction set (thesis 000 Chapter 6, future work: "expand the
system with regard to multiple robots"), ROS-free.

Timing rule of a fleet (the single robot's rule of `problem`, per robot): robot r stands on
`starts[r].node` and is free from `starts[r].free_at`; it drives shortest paths at the problem's
speed and serves its instructions one after the other. An instruction starts no earlier than its
launch, its robot's arrival and its predecessor's completion (`previous_id`, served by any robot),
takes its `duration`, and earns Eq. 4-2 at its completion. The fleet's reward is the sum.

`run_fleet` runs an allocator online: instructions appear at their launch, the robot that is free
first decides next, and an instruction a robot decided to serve is claimed (no other robot takes
it). Allocators: `PerRobotPlanners` (the seed's planner extended greedily: each robot runs a
single-robot planner on the instructions nobody has claimed) and `SequentialAuction`. The exact
optimum over all assignments and orders is `fleet_exact.fleet_exact_optimum`.
"""
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal, Protocol, cast, overload

import numpy as np

from task_planner.planner_api import NODE, TARGET, NodePlanner, Planner, TargetPlanner, kind_of
from task_planner.problem import Problem
from task_planner.reward import decayed_reward


@dataclass(frozen=True)
class RobotStart:
    """Where a robot stands and from when it is free [s] (busy until then)."""

    node: int
    free_at: float = 0.0


class FleetDeadlock(ValueError):
    """The robots' orders and the instruction chains wait on each other."""


def check_starts(problem: Problem, starts: Sequence[RobotStart]) -> None:
    """ValueError naming the robot whose start is outside the graph or not a finite time."""
    if not starts:
        raise ValueError("a fleet needs at least one robot")
    for r, start in enumerate(starts):
        if not 0 <= start.node < problem.graph.size:
            raise ValueError(f"robot {r}: start node {start.node} is not in the graph")
        if not np.isfinite(start.free_at) or start.free_at < 0:
            raise ValueError(f"robot {r}: free_at must be a finite time >= 0, "
                             f"got {start.free_at}")


def service_end(problem: Problem, node: int, clock: float, index: int, after: float = 0.0) -> float:
    """The timing rule of one service: a robot free at `clock` [s] on `node` drives the shortest
    path to instruction `index`, starts no earlier than its launch and `after` (its
    predecessor's completion), and is done after its duration -> completion [s]."""
    arrive = clock + problem.travel_s[node, problem.node[index]]
    return max(arrive, problem.launch[index], after) + problem.duration[index]


def fleet_completion(problem: Problem, orders: Sequence[Sequence[int]],
                     starts: Sequence[RobotStart]) -> dict[int, float]:
    """Completion time [s] of every served instruction (dict index -> time) when robot r serves
    `orders[r]` in order under the fleet's timing rule.

    Raises FleetDeadlock when an instruction's predecessor is served by nobody or the orders and
    chains wait on each other; ValueError when an instruction is in two orders.
    """
    check_starts(problem, starts)
    if len(orders) != len(starts):
        raise ValueError(f"{len(orders)} orders for {len(starts)} robots")
    listed = [int(i) for order in orders for i in order]
    if len(set(listed)) != len(listed):
        raise ValueError("an instruction is in two orders (or twice in one)")
    p = problem
    position, node = [0] * len(orders), [s.node for s in starts]
    clock, done = [float(s.free_at) for s in starts], dict[int, float]()
    while len(done) < len(listed):
        progressed = False
        for r, order in enumerate(orders):
            while position[r] < len(order):
                i = int(order[position[r]])
                before = int(p.predecessor[i])
                if before >= 0 and before not in done:
                    if before not in listed:
                        raise FleetDeadlock(f"instruction {p.ids[i]} is served but its "
                                            f"predecessor {p.ids[before]} is not")
                    break
                clock[r] = service_end(p, node[r], clock[r], i, done.get(before, 0.0))
                node[r] = int(p.node[i])
                done[i] = clock[r]
                position[r] += 1
                progressed = True
        if not progressed:
            raise FleetDeadlock("the robots' orders and the instruction chains wait on each "
                                "other")
    return done


def completion_reward(problem: Problem, completion: Mapping[int, float]) -> float:
    """Sum of Eq. 4-2 over a dict index -> completion time [s]."""
    if not completion:
        return 0.0
    index = np.fromiter(completion, dtype=int)
    finish = np.fromiter(completion.values(), dtype=float)
    return float(decayed_reward(problem.gamma[index], problem.beta[index],
                                finish - problem.launch[index]).sum())


def fleet_reward(problem: Problem, orders: Sequence[Sequence[int]],
                 starts: Sequence[RobotStart]) -> float:
    """The fleet's accumulated reward (sum of Eq. 4-2) of serving `orders`."""
    return completion_reward(problem, fleet_completion(problem, orders, starts))


@dataclass
class FleetRun:
    """What an allocator did: each robot's service order and every completion time."""

    orders: list[list[int]]                          # per robot: instruction indices in order
    completion: dict[int, float]                     # index -> completion time [s]
    decision_calls: list[float] = field(default_factory=list)  # wall time of each decision [s]

    def reward(self, problem: Problem) -> float:
        return completion_reward(problem, self.completion)


@dataclass
class FleetView:
    """What an allocator may know when robot `robot` decides: every robot's node and the time it
    is free, the instructions launched so far that nobody has claimed (`open`), and the
    completion times of the claimed ones (`done`, possibly in the future)."""

    robot: int
    nodes: list[int]
    clocks: list[float]
    open: np.ndarray
    done: dict[int, float]


class Allocator(Protocol):
    """Decides for the robots of a fleet (`run_fleet`): reset with the problem and the robots'
    starts, then asked by the robot that is free first."""

    def reset(self, problem: Problem, starts: Sequence[RobotStart]) -> None: ...

    def decide(self, view: FleetView, available: np.ndarray) -> tuple[str, int | None]: ...


def idle_step(allocator: Allocator, view: FleetView) -> int | None:
    """The neighbour an allocator sends a waiting robot to (its optional `idle(view)`), or None:
    the robot stays where it is."""
    idle = getattr(allocator, "idle", None)
    return None if idle is None else idle(view)


def run_fleet(problem: Problem, starts: Sequence[RobotStart], allocator: Allocator) -> FleetRun:
    """Run `allocator` online on `problem` with robots at `starts`; returns a FleetRun.

    The free robot with the earliest clock decides: it is given the instructions it could start
    now (launched, unclaimed, predecessor completed). The allocator answers ("serve", i) for one
    on the robot's node, ("move", neighbour), ("target", i) (drive there and serve it; claimed at
    once) or ("wait", None) (decide again after the next event: a launch, a completion, another
    robot becoming free). A robot that waits, or has nothing it could start, first drives the
    edge `idle_step` names, if any (towards its waiting place).
    """
    check_starts(problem, starts)
    p = problem
    allocator.reset(p, starts)
    robots = [_Robot(s.node, float(s.free_at)) for s in starts]
    pending, done = set(range(p.count)), dict[int, float]()
    run = FleetRun(orders=[[] for _ in starts], completion=done)
    while pending:
        r = min(range(len(robots)), key=lambda k: (robots[k].clock, robots[k].yielded, k))
        robot = robots[r]
        available = _available(p, pending, done, robot.clock)
        view = FleetView(r, [b.node for b in robots], [b.clock for b in robots],
                         _known(p, pending, robot.clock), done)
        action, value = _ask(allocator, view, available, run)
        if action == "wait":
            if not len(available):
                robot.clock = _next_event(p, pending, done, robots, robot.clock)
            else:
                _wait(p, pending, done, robots, r)
            continue
        for b in robots:
            b.yielded = False
        if value is None:
            raise RuntimeError(f"allocator answered {action!r} for robot {r} without a node or "
                               f"an instruction")
        if action == "move":
            length_s = p.edge_s[robot.node, value]
            if length_s <= 0:
                raise RuntimeError(f"allocator moved robot {r} from node {robot.node} to "
                                   f"non-neighbour {value}")
            robot.clock += length_s
            robot.node = int(value)
            continue
        index = int(value)
        if index not in available:
            raise RuntimeError(f"allocator gave robot {r} instruction {index}, which it cannot "
                               f"start now")
        if action == "serve" and p.node[index] != robot.node:
            raise RuntimeError(f"allocator served instruction {index} away from its node")
        robot.clock += float(p.travel_s[robot.node, p.node[index]])
        robot.node = int(p.node[index])
        robot.clock = max(robot.clock, p.launch[index]) + p.duration[index]
        pending.discard(index)
        done[index] = robot.clock
        run.orders[r].append(index)
    return run


def _ask(allocator: Allocator, view: FleetView, available: np.ndarray,
         run: FleetRun) -> tuple[str, int | None]:
    """The allocator's answer for the deciding robot (timed), a move towards its waiting place
    instead of a wait, or a wait when it could start nothing."""
    action, value = "wait", None
    if len(available):
        started = time.perf_counter()
        action, value = allocator.decide(view, available)
        run.decision_calls.append(time.perf_counter() - started)
    step = idle_step(allocator, view) if action == "wait" else None
    return ("move", step) if step is not None else (action, value)


def _wait(p: Problem, pending: set[int], done: Mapping[int, float], robots: list["_Robot"],
          r: int) -> None:
    """Robot r waits although it could start something: until the next event, or after the
    others at its time decided."""
    robot = robots[r]
    later = _next_event(p, pending, done, robots, robot.clock, strict=True)
    if later is not None:
        robot.clock = later
    elif any(b.clock == robot.clock and not b.yielded for k, b in enumerate(robots) if k != r):
        robot.yielded = True          # let the others at this time decide first
    else:
        raise RuntimeError(f"allocator: robot {r} waits while instructions are "
                           f"available and nothing else can happen")


@dataclass
class _Robot:
    node: int
    clock: float
    yielded: bool = False    # waited at this clock for the others to decide first


def _available(p: Problem, pending: set[int], done: Mapping[int, float],
               clock: float) -> np.ndarray:
    return np.array(sorted(i for i in pending if p.launch[i] <= clock and (
        p.predecessor[i] < 0 or done.get(int(p.predecessor[i]), np.inf) <= clock)), dtype=int)


def _known(p: Problem, pending: set[int], clock: float) -> np.ndarray:
    return np.array(sorted(i for i in pending if p.launch[i] <= clock), dtype=int)


@overload
def _next_event(p: Problem, pending: set[int], done: Mapping[int, float],
                robots: Sequence[_Robot], clock: float,
                strict: Literal[False] = False) -> float: ...


@overload
def _next_event(p: Problem, pending: set[int], done: Mapping[int, float],
                robots: Sequence[_Robot], clock: float, strict: bool) -> float | None: ...


def _next_event(p: Problem, pending: set[int], done: Mapping[int, float], robots: Sequence[_Robot],
                clock: float, strict: bool = False) -> float | None:
    """The earliest time after `clock` at which something may change: a launch, a completion,
    another robot's clock. None (strict) or RuntimeError when there is none."""
    times = [p.launch[i] for i in pending if p.launch[i] > clock]
    times += [t for t in done.values() if t > clock]
    times += [b.clock for b in robots if b.clock > clock]
    if times:
        return float(min(times))
    if strict:
        return None
    raise RuntimeError("pending instructions can never become available")


class PerRobotPlanners:
    """The seed's planner extended to a fleet greedily: every robot runs its own single-robot
    planner (a node or target planner of `planner_registry`) on the instructions nobody has
    claimed. Robots do not coordinate; two may head for the same instruction, and the one that
    arrives first serves it."""

    def __init__(self, make_planner: Callable[[], Planner], name: str) -> None:
        self.make_planner, self.name = make_planner, name

    def reset(self, problem: Problem, starts: Sequence[RobotStart]) -> None:
        self.planners = [self.make_planner() for _ in starts]
        for planner in self.planners:
            planner.reset(problem)

    def decide(self, view: FleetView, available: np.ndarray) -> tuple[str, int | None]:
        planner = self.planners[view.robot]
        node, clock = view.nodes[view.robot], view.clocks[view.robot]
        if kind_of(planner) == NODE:
            return cast(NodePlanner, planner).decide(node, clock, available)
        if kind_of(planner) == TARGET:
            return "target", cast(TargetPlanner, planner).choose(node, clock, available)
        raise ValueError(f"{planner.name}: a fleet robot runs node or target planners")
