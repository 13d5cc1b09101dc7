"""A planning problem as arrays, and the timing rule that scores any executed route.

Time model (seconds): the robot starts on `start_node` at t = 0 and drives graph edges at
`speed_mps`. At each route position it serves the instructions listed for that position in order;
an instruction cannot start before its launch and takes `duration` seconds; its reward is
Eq. 4-2 with t = completion - launch. Before leaving a position the robot may wait until a given
time (idle robot waiting for the next launch in dynamic runs; a step planner's steps beyond the
edge it finally drives). A node repeated in the route costs no travel: the robot left it and
turned back, and the wait before says when it was back.
"""
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from task_planner.graph import TopologicalGraph
from task_planner.instruction import Instruction
from task_planner.instruction_set import validate_instruction_set
from task_planner.reward import decayed_reward


@dataclass(frozen=True)
class Problem:
    """Graph, robot speed and start node, and the instructions as parallel arrays."""

    graph: TopologicalGraph
    instructions: tuple[Instruction, ...]  # index = position in the arrays below
    speed_mps: float = 0.5   # navigation speed [m/s]
    start_node: int = 0
    # parallel arrays derived in __post_init__ (read-only), not arguments
    ids: np.ndarray = field(init=False, repr=False, compare=False)
    gamma: np.ndarray = field(init=False, repr=False, compare=False)
    beta: np.ndarray = field(init=False, repr=False, compare=False)
    node: np.ndarray = field(init=False, repr=False, compare=False)
    duration: np.ndarray = field(init=False, repr=False, compare=False)
    launch: np.ndarray = field(init=False, repr=False, compare=False)
    predecessor: np.ndarray = field(init=False, repr=False, compare=False)
    travel_s: np.ndarray = field(init=False, repr=False, compare=False)
    edge_s: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not self.speed_mps > 0:
            raise ValueError(f"speed_mps must be > 0, got {self.speed_mps}")
        if not 0 <= self.start_node < self.graph.size:
            raise ValueError(f"start node {self.start_node} is not in the graph")
        validate_instruction_set(self.instructions, self.graph.size)
        index = {ins.id: k for k, ins in enumerate(self.instructions)}
        arrays = dict(
            ids=np.array([i.id for i in self.instructions], dtype=int),
            gamma=np.array([i.gamma for i in self.instructions], dtype=float),
            beta=np.array([i.beta for i in self.instructions], dtype=float),
            node=np.array([i.destination for i in self.instructions], dtype=int),
            duration=np.array([i.duration for i in self.instructions], dtype=float),
            launch=np.array([i.start_time for i in self.instructions], dtype=float),
            predecessor=np.array([index.get(i.previous_id, -1) for i in self.instructions],
                                 dtype=int),
            travel_s=self.graph.shortest / self.speed_mps,   # (V, V) [s]
            edge_s=self.graph.adjacency / self.speed_mps,    # (V, V) [s], 0 = no edge
        )
        for name, value in arrays.items():
            value.setflags(write=False)
            object.__setattr__(self, name, value)

    @property
    def count(self) -> int:
        return len(self.instructions)


@dataclass
class Schedule:
    """What a planner did: route, who was served where, and the resulting times and rewards."""

    route: list[int]                     # node indices, consecutive ones adjacent or equal (the
    #                                      robot left the node and turned back: see waits)
    served: list[tuple[int, int]]        # [(instruction index, route position)] in service order
    waits: dict[int, float] = field(default_factory=dict)  # route position -> depart not before [s]
    decision_before: list[float] = field(default_factory=list)  # cumulative decision time per
    #                                                             serve [s]
    decision_s: float = 0.0              # total decision time [s]
    decision_calls: list[float] = field(default_factory=list)  # wall time of each planner call [s]
    decision_cpu_calls: list[float] = field(default_factory=list)  # thread CPU time per call [s]
    completion: np.ndarray | None = None  # per served entry: completion time [s]
    guard_activations: int = 0           # loop-guard activations (the seed's planner only)


def score_route(problem: Problem, route: Sequence[int], served: Sequence[tuple[int, int]],
                waits: Mapping[int, float] | None = None) -> np.ndarray:
    """Completion times [s] (per `served` entry) of executing `route` under the timing rule."""
    waits = waits or {}
    by_position: dict[int, list[int]] = {}
    for index, position in served:
        by_position.setdefault(position, []).append(index)
    clock = 0.0
    completion: dict[int, float] = {}
    for position, node in enumerate(route):
        if position and route[position - 1] != node:  # a repeated node: left and came back
            length_s = problem.edge_s[route[position - 1], node]
            if length_s <= 0:
                raise ValueError(f"route steps {route[position - 1]} -> {node}: not an edge")
            clock += length_s
        for index in by_position.get(position, []):
            clock = max(clock, problem.launch[index]) + problem.duration[index]
            completion[index] = clock
        clock = max(clock, waits.get(position, 0.0))
    return np.array([completion[index] for index, _ in served])


def schedule_reward(problem: Problem, schedule: Schedule, with_decision: bool = False) -> float:
    """Accumulated reward (sum of Eq. 4-2) of a scored schedule, optionally delayed by decisions."""
    if not schedule.served:
        return 0.0
    served = np.array([index for index, _ in schedule.served])
    completion = _completion(schedule)
    if with_decision:
        completion = completion + np.asarray(schedule.decision_before)
    elapsed = completion - problem.launch[served]
    return float(decayed_reward(problem.gamma[served], problem.beta[served], elapsed).sum())


def _completion(schedule: Schedule) -> np.ndarray:
    """The schedule's completion times; ValueError for a schedule that was never scored."""
    if schedule.completion is None:
        raise ValueError("schedule has served entries but no completion times (not scored)")
    return schedule.completion


def order_to_schedule(problem: Problem, order: Sequence[int] | np.ndarray) -> Schedule:
    """Route and service list of serving instructions in `order`, driving shortest paths."""
    route, served = [problem.start_node], []
    for index in order:
        target = int(problem.node[index])
        route += problem.graph.path(route[-1], target)[1:]
        served.append((int(index), len(route) - 1))
    schedule = Schedule(route=route, served=served)
    schedule.completion = score_route(problem, route, served)
    return schedule


def order_reward(problem: Problem, order: Sequence[int] | np.ndarray) -> float:
    """Reward of serving `order` from the start at t = 0 (no decision time)."""
    return schedule_reward(problem, order_to_schedule(problem, order))


def respects_chains(problem: Problem, order: Sequence[int] | np.ndarray) -> bool:
    """True when every instruction comes after its predecessor (if that is in the set)."""
    position = {int(index): k for k, index in enumerate(order)}
    before = problem.predecessor
    return all(before[i] < 0 or position[int(before[i])] < position[int(i)] for i in order)
