"""What the executor's behaviours share (ROS-free): the robot's collaborators, its state, and the
event being handled. The behaviour tree (task_planner.behaviours.tree) and the functions of the
behaviour modules read and change one Context; commands for the robot collect in `out`.
"""
import math
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Literal

import py_trees
from py_trees.common import Status

from task_planner.battery import BatteryModel
from task_planner.executor_commands import (EXECUTING, IDLE, LOOKING, MOVING, VERIFYING, Command,
                                           Navigate)
from task_planner.fleet_auction import SequentialAuction
from task_planner.fleet_link import FleetLink
from task_planner.graph import TopologicalGraph
from task_planner.instruction import Instruction
from task_planner.people_belief import PeopleAtPlaces
from task_planner.planner_api import Planner
from task_planner.problem import Problem
from task_planner.reward import Priority
from task_planner.robot_functions import RobotFunction
from task_planner.task_buffer import Record, TaskBuffer


OVERDUE_ORDERS = ("smith", "oldest")   # deciding.overdue_first


@dataclass(frozen=True)
class ExecutorConfig:
    speed_mps: float = 0.5        # robot speed along graph edges, for the planners [m/s]
    max_goal_attempts: int = 3    # navigation attempts per goal before its instruction fails
    latency_window: int = 1000    # decisions whose wall time is kept (decision_s)
    battery_save_wh: float = 0.5  # journal the battery level when it moved this much [Wh]
    verify_wait_s: float = 0.0    # look for an absent target person this long on arrival [s]
    look_headings: int = 0        # turns in place to look around a place (0: stand, as above)
    look_dwell_s: float = 0.0     # stay on each heading this long, perception catching up [s]
    look_frames: int = 0          # and until perception analysed this many frames taken there,
                                  # so a loaded machine looks as long as an idle one (0: dwell)
    look_frames_wait_s: float = 10.0  # but turn on after this long on a heading all the same;
                                  # a person seen there whom perception cannot tell is faced
                                  # and watched this long [s]
    ask_wait_s: float = 0.0       # still unable to tell them after that watch, the robot asks
                                  # them whether they are the person it looks for and waits
                                  # this long for a yes to reach its belief [s] (0: never asks)
    look_again_s: float = 0.0     # a place looked all around this recently is not looked around
                                  # again: whoever that look saw is here, anyone else is
                                  # searched for elsewhere at once [s] (0: look every time)
    fresh_s: float = math.inf     # a sighting this old counts as "the person is here" [s]
    stranger_fresh_s: float = 0.0  # an introduce instruction is served once perception saw
                                  # someone it cannot tell at the place this recently,
                                  # else the robot looks around for them [s] (0: greet
                                  # on arrival)
    search_all_places: bool = False  # search every place, not only the last known ones
    follow_belief: bool = False   # serve a person where the robot believes them (else: where
                                  # the instruction says, until a search begins)
    search_miss_s: float = 0.0    # following the belief, what a miss costs (the look around,
                                  # the call, the drive on) [s]: the planner takes a person's
                                  # instruction to last the chance of one times this longer
                                  # (searching.served_where; 0: it ignores misses, as the seed)
    stay_s: float = 600.0         # the mean time a person stays at a place (miss_chance) [s]
    pass_wait_s: float = 0.0      # after an abort ask to pass and wait this long [s] (0: no)
    pass_request: str = "Excuse me, may I pass?"
    patrol: bool = False          # look at stale places while idle
    own_yields: bool = False      # a person's request interrupts the robot's own instruction
    own_kept: tuple = ("charge", "introduce")  # own functions that are never interrupted
    meetings_inherit: bool = False  # a stranger's meeting takes the priority of the strongest
                                  # person's request waiting for a meeting (planner only)
    serve_within_s: float = 0.0   # instructions launched this long ago are served before any
                                  # newer one (deciding.overdue_first) [s] (0: Eq. 4-2's
                                  # reward alone decides, as the seed)
    overdue_order: str = "smith"  # among overdue instructions: "smith" (most priority per
                                  # second of the robot's time: the least weighted completion
                                  # time) or "oldest" first (the least maximum lateness)
    yield_notice: str = "Excuse me, I am needed elsewhere. I will be back."
    patrol_interval_s: float = 60.0  # a place looked at this recently is not patrolled [s]
    never_looked_s: float = 600.0  # how stale the patrol takes a place never looked at [s]
    pass_through: tuple = ()      # graph nodes people only pass through (an alley, the dock):
                                  # patrolled only while the belief or a schedule puts someone
                                  # there, searched after every other place
    corridors: tuple = ()         # graph nodes one robot of a fleet at a time drives through
    corridor_wait_s: float = 60.0  # wait this long for a corridor, then drive on [s]; an
                                  # instruction given back to the fleet is left to the others
                                  # this long
    max_handbacks: int = 2        # in a fleet, an instruction whose place the robot cannot
                                  # reach goes back to the pool this many times, then fails
    corridor_poll_s: float = 1.0  # look again whether the corridor is free this often [s]
    one_robot_per_place: bool = False  # in a fleet, leave the instructions at a place to the
                                  # robot that holds one there (small rooms fit one robot)
    max_open: int = 0             # new instructions from outside beyond this many open ones
                                  # are refused (behaviours.receiving; 0: no cap)
    fleet_allocator: str = "auction"  # in a fleet, a fleet_registry allocator: `auction` decides
                                  # over the whole fleet (behaviours.fleet_allocation); a
                                  # per-robot one (`seed`, `rollout`): the robot's own planner
                                  # on the instructions no other robot holds
    claim_wait_s: float = 5.0     # an instruction the auction gives another robot that has
                                  # not claimed it this long after it said it would be free is
                                  # this robot's to take [s]

    def __post_init__(self) -> None:
        if self.overdue_order not in OVERDUE_ORDERS:
            raise ValueError(f"overdue_order must be one of {OVERDUE_ORDERS}, got "
                             f"{self.overdue_order!r}")


@dataclass(frozen=True)
class Charging:
    """The low-battery rule: where to charge, with which function code and priority."""

    battery: BatteryModel
    place: int             # charging place (graph node)
    function_code: int     # robot function `charge`
    priority: Priority     # of self-generated instructions (Table 5-5)


def _no_tree(now: float) -> list[Command]:
    raise RuntimeError("the executor's behaviour tree is not built: no decide hook "
                       "(tree.build_tree sets it)")


# the events the tree handles: a periodic step, a navigation outcome, new instructions, a cancel
TICK, ARRIVED, ABORTED, RECEIVED, CANCELLED = "tick", "arrived", "aborted", "received", "cancelled"


@dataclass(eq=False)
class Context:
    """The executor's collaborators and state, shared by its behaviours."""

    buffer: TaskBuffer             # the journal of instructions
    graph: TopologicalGraph        # the home's topological graph
    planner: Planner               # a node or target planner
    people: PeopleAtPlaces         # where people were seen
    functions: dict[int, RobotFunction]  # robot function code -> its RobotFunction
    config: ExecutorConfig
    node: int                      # last node reached
    node_planner: bool = True      # the planner decides node by node (else: targets)
    charging: Charging | None = None  # None: a robot without a battery model
    fleet: FleetLink | None = None  # None for a robot on its own
    allocator: SequentialAuction | Literal[False] | None = None  # the fleet's auction
                                   # (fleet_allocation builds it at first use; False: the
                                   # allocator is per-robot)
    mode: str = IDLE
    goal: int | None = None        # node being driven to while MOVING
    goal_for: int = 0              # instruction id the current move is for
    serve_at: int | None = None    # where the move's instruction is to be served, as decided
    rethought_on: tuple[int, int | None] | None = None  # (node, goal) of the leg on which
                                   # seen_elsewhere last decided again
    attempts: int = 0              # navigation attempts on the current goal
    leg_start: tuple[float, float] = (0.0, 0.0)  # (when [s], travel time from `node` [s])
                                   # the robot set off toward `goal` from: 0 from the node,
                                   # more after a turn back mid-edge (where_on_leg)
    blocked: tuple[int, float] | None = None  # (goal, since [s]) while another robot of the
                                   # fleet at that goal keeps the path blocked
    executing: tuple[int, float] | None = None  # (instruction id, end time [s]) while EXECUTING
    verifying: tuple[int, float] | None = None  # (instruction id, give-up time [s]) while
                                                # VERIFYING
    looking: list | None = None    # [instruction id (0: patrol), headings left, since, end of
                                   #  the last heading's dwell (None: turning), when that
                                   #  heading was reached, facing someone perception could
                                   #  not tell (None, FACING, ASKING, FACED)] while LOOKING
    faced: list[tuple[float, float]] = field(default_factory=list)  # (x, y) [m] of the people
                                   # this look faced (each a different person to ask)
    search: dict[int, list[int]] = field(default_factory=dict)  # instruction id -> places
                                                  # still to search
    searched: dict[int, list[int]] = field(default_factory=dict)  # instruction id -> places
                                                  # already searched
    search_start: dict[int, float] = field(default_factory=dict)  # instruction id -> its
                                                  # first miss [s]
    rechecked: dict[int, set[int]] = field(default_factory=dict)  # instruction id -> places
                                                  # looked at again (searching.look_again_at)
    looked_s: dict[int, float] = field(default_factory=dict)  # node -> when the robot last
                                                  # looked there [s]
    swept: dict[int, tuple[float, float]] = field(default_factory=dict)  # node -> (start, end)
                                                  # [s] of the last look that turned through
                                                  # every heading there
    retry_at: float | None = None  # when to retry an aborted goal after asking to pass, or
                                   # to look again whether a corridor is free [s]
    corridor_wait: float | None = None  # since when the robot waits for a corridor [s]
    deferred: set[int] = field(default_factory=set)  # own instructions waiting for people's
    lost_claims: set[int] = field(default_factory=set)  # ids another robot held at the claim
    waiting_places: dict[int, tuple[int, ...]] = field(default_factory=dict)  # fleet size ->
                                   # its k-median places (fleet_allocation.wait_at_place)
    alone_since: float | None = None  # since when no other robot of the fleet reported [s]
    waiting_for: tuple[tuple[str, ...], int] | None = None  # (the fleet's robots, place) of
                                   # the waiting place the idle robot drives to
                                   # (fleet_allocation.wait_at_place)
    wait_given_up: tuple[int, float] | None = None  # (node, when [s]) a drive to a waiting
                                   # place was given up at (recovery.recover)
    given_back: dict[int, tuple[float, int]] = field(default_factory=dict)  # id -> (when [s],
                                   # times) the robot gave it back, its place out of reach
    taken: set[int] = field(default_factory=set)  # ids other robots held at this decision's
                                   # fetch
    unclaimed: dict[int, float] = field(default_factory=dict)  # id -> when the robot the
                                   # auction gives it to first said it would be free
                                   # (fleet_allocation.overdue)
    reported: tuple[str, int, float] | None = None  # (mode, node, free from [s]) last reported
                                                    # to the fleet
    patrol_goal: int | None = None  # place an idle patrol is driving to
    problem_key: tuple | None = None  # the instructions the cached problem was made from
    problem: Problem | None = None  # of the open instructions
    target: tuple[Problem, int] | None = None    # (problem, index) a target planner is driving to
    saved_wh: float | None = None  # battery level last journalled [Wh]
    in_fleet: bool = False         # rejoined the fleet (at the first event with a time)
    owed: list[Command] = field(default_factory=list)  # commands of an event that raised
                                   # afterwards
    log: list[tuple[float, str]] = field(default_factory=list)  # (time [s], event text): why
                                   # each move was made
    decision_s: deque[float] = field(default_factory=deque)  # wall time of the latest
                                   # decisions
    decision_cpu_s: deque[float] = field(default_factory=deque)  # and their thread CPU time [s]
    # (now) -> commands: decide at the robot's node; decide again on news (both set by
    # tree.build_tree to task_planner.behaviours.deciding's)
    decide: Callable[[float], list[Command]] = _no_tree
    redecide: Callable[[float], list[Command]] = _no_tree
    # the event being handled
    event: str = TICK
    now: float = 0.0
    reason: str = ""               # why navigation gave up (ABORTED)
    inbox: list[Instruction] = field(default_factory=list)  # instructions to journal
                                   # (RECEIVED)
    results: list[tuple[Record | None, str]] = field(default_factory=list)  # (record, error)
                                   # per instruction taken in
    cancelled: Record | None = None  # the record to withdraw as it was before the event
                                   # (CANCELLED)
    synced: list[Command] = field(default_factory=list)   # commands of this event's fleet
                                   # rejoin
    out: list[Command] = field(default_factory=list)      # commands for the robot

    def serving(self) -> int:
        """Id of the instruction the robot is moving for, looking for, verifying or executing
        (0 when idle or patrolling)."""
        if self.mode == MOVING:
            return self.goal_for
        if self.mode == LOOKING:
            return int(self.looking_now()[0])
        if self.mode == VERIFYING:
            return self.verifying_now()[0]
        if self.mode == EXECUTING:
            return self.executing_now()[0]
        return 0

    # the state of the mode the robot is in; RuntimeError naming the mode when it is unset (the
    # mode says it is set: a broken invariant, never a robot's ordinary state)

    def executing_now(self) -> tuple[int, float]:
        """(instruction id, end time [s]) of the function being executed."""
        if self.executing is None:
            raise RuntimeError(f"executor in mode {self.mode}: no function is executing")
        return self.executing

    def verifying_now(self) -> tuple[int, float]:
        """(instruction id, give-up time [s]) of the target being verified."""
        if self.verifying is None:
            raise RuntimeError(f"executor in mode {self.mode}: no target is being verified")
        return self.verifying

    def looking_now(self) -> list:
        """The look around under way (`looking`)."""
        if self.looking is None:
            raise RuntimeError(f"executor in mode {self.mode}: no look around is under way")
        return self.looking

    def goal_now(self) -> int:
        """The node being driven to."""
        if self.goal is None:
            raise RuntimeError(f"executor in mode {self.mode}: no navigation goal")
        return self.goal

    def set_off(self, now: float, from_node_s: float = 0.0) -> None:
        """The robot sets off toward `goal` at `now` [s], `from_node_s` [s] of travel from
        `node` (0: from the node itself)."""
        self.leg_start = (now, from_node_s)

    def where_on_leg(self, now: float) -> tuple[float, float]:
        """(travel time back to `node`, on to `goal`) [s] while driving, estimated from the
        time driven since the robot set off at `speed_mps` (waits after an abort count as
        driven: the estimate never goes past the goal)."""
        edge_s = float(self.graph.shortest[self.node, self.goal_now()]) / self.config.speed_mps
        started, from_node_s = self.leg_start
        back_s = min(max(from_node_s + now - started, 0.0), edge_s)
        return back_s, edge_s - back_s

    def navigate(self) -> Navigate:
        """The move to the goal node; a waypoint (a node on the way to the place the move is
        for: the instruction's or the patrol's) carries the heading on to the node after it,
        so navigation may pass it without stopping (when the graph has poses)."""
        goal = self.goal_now()
        bound = self.serve_at if self.goal_for else self.patrol_goal
        if bound is None or bound == goal or self.graph.poses is None:
            return Navigate(goal, self.goal_for)
        after = int(self.graph.next_hop[goal, bound])
        (x0, y0, _), (x1, y1, _) = self.graph.poses[goal], self.graph.poses[after]
        return Navigate(goal, self.goal_for, through=math.atan2(y1 - y0, x1 - x0))

    def left_to_others(self, now: float) -> set[int]:
        """Ids the robot gave back to its fleet within corridor_wait_s: not for it now."""
        return {i for i, (when, _) in self.given_back.items()
                if now - when < self.config.corridor_wait_s}

    def fleet_now(self) -> FleetLink:
        """The robot's link to its fleet."""
        if self.fleet is None:
            raise RuntimeError("the robot is on its own (fleet is None)")
        return self.fleet

    def charging_now(self) -> Charging:
        """The low-battery rule of a robot with a battery model."""
        if self.charging is None:
            raise RuntimeError("the robot has no battery model (charging is None)")
        return self.charging

    def corridors_of(self, nodes: Iterable[int | None]) -> set[str]:
        """The names of the corridors among graph nodes `nodes`."""
        return {self.graph.names[n] for n in nodes
                if n is not None and n in self.config.corridors}


class Leaf(py_trees.behaviour.Behaviour):
    """A leaf of the executor's tree: `step(ctx)` runs it and returns its status (success,
    failure or running); a leaf that is not for the event or the mode fails, so a selector
    tries the next one."""

    def __init__(self, name: str, ctx: Context) -> None:
        super().__init__(name)
        self.ctx = ctx

    def update(self) -> Status:
        return self.step(self.ctx)

    def step(self, ctx: Context) -> Status:
        raise NotImplementedError


class Action(Leaf):
    """A leaf that always runs `act(ctx)` (returning commands) and succeeds."""

    def __init__(self, name: str, ctx: Context, act: Callable[[Context], list[Command]]) -> None:
        super().__init__(name, ctx)
        self.act = act

    def step(self, ctx: Context) -> Status:
        ctx.out += self.act(ctx)
        return Status.SUCCESS


class IsEvent(Leaf):
    """Succeeds when the event being handled is `event`."""

    def __init__(self, ctx: Context, event: str) -> None:
        super().__init__(f"{event}?", ctx)
        self.event = event

    def step(self, ctx: Context) -> Status:
        return Status.SUCCESS if ctx.event == self.event else Status.FAILURE


def still_busy(ctx: Context, mode: str) -> Status:
    """RUNNING while the robot is still in `mode`; FAILURE once its step changed the mode, so
    the next leaves of the activity selector (each for its own mode) take their turn in the
    same tick: a look that ended in a move may drive, a robot gone idle decides."""
    return Status.RUNNING if ctx.mode == mode else Status.FAILURE
