"""The decision (ROS-free), thesis 000 §4.2.5 Fig. 4-14: fetch the open instructions, decode
them into a planning problem (reward, decay factor, destination, chains), ask the configured
planner, then serve here or drive to the next neighbouring node. New instructions re-decide at
once; while driving the decision is taken from the end of the edge the robot is nearer to (by
the time it has driven) and may turn the robot back mid-edge (§4 "dynamic"). With nothing to
decide an idle robot may patrol. In a fleet the robot decides among the instructions no other
robot holds (with the fleet's auction, behaviours.fleet_allocation, or its own planner) and
claims its choice before it drives.
"""
import math
import time
from dataclasses import replace
from collections.abc import Container, Sequence
from typing import cast

import numpy as np
from py_trees.common import Status

from task_planner.behaviours.context import Context, Leaf
from task_planner.behaviours.driving import drive
from task_planner.behaviours.fleet_allocation import (auction_choice, fleet_allocator, report_free,
                                                      travel_s, wait_at_place)
from task_planner.behaviours.looking import serve_here
from task_planner.behaviours.patrolling import clear_corridor, patrol
from task_planner.behaviours.searching import served_where
from task_planner.executor_commands import EXECUTING, IDLE, LOOKING, MOVING, VERIFYING, \
    Command, StopMotion
from task_planner.instruction import HUMAN, Instruction
from task_planner.planner_api import NodePlanner, TargetPlanner
from task_planner.problem import Problem
from task_planner.robot_functions import is_meeting
from task_planner.task_buffer import PENDING, Record



def decide(ctx: Context, now: float) -> list[Command]:
    """Fetch, decode, decide at the robot's node; returns the commands of the decision (and
    tells the fleet where and when the robot will be free then)."""
    commands = decide_here(ctx, now)
    report_free(ctx, now)
    return commands


def decide_here(ctx: Context, now: float) -> list[Command]:
    commands: list[Command] = []
    ctx.lost_claims.clear()
    while True:
        decision = timed_decision(ctx, now)
        if decision is None:
            if ctx.fleet:
                ctx.fleet.release()
            idle = patrol(ctx, now) if ctx.config.patrol else wait_at_place(ctx, now)
            return commands + (idle or clear_corridor(ctx, now))
        problem, index, step = decision
        instruction_id = int(problem.ids[index])
        if ctx.fleet and not ctx.fleet.claim(instruction_id, now, int(problem.node[index])):
            ctx.lost_claims.add(instruction_id)
            continue  # another robot took it first: choose among the rest
        ctx.waiting_for = None   # serving: idle again, it chooses its waiting place afresh
        if step is None:
            commands += serve_here(ctx, instruction_id, now)
            if ctx.mode in (EXECUTING, VERIFYING, LOOKING):
                return commands
            continue  # failed, or the person is searched elsewhere: decide again
        ctx.mode, ctx.goal, ctx.goal_for, ctx.attempts = MOVING, step, instruction_id, 1
        ctx.set_off(now)
        ctx.patrol_goal, ctx.serve_at = None, int(problem.node[index])
        ctx.log.append((now, f"move {ctx.graph.names[ctx.node]} -> "
                             f"{ctx.graph.names[step]} for {instruction_id}"))
        return commands + drive(ctx, now)


def redecide(ctx: Context, now: float) -> list[Command]:
    """Decide again on news: a patrol gives way at once; an idle robot decides; a driving
    robot may turn back mid-edge, or, when the fleet's auction gives what it drives for to
    another robot, give it back and drive on to the next node (deciding there). A robot
    function, the look for its person and a wait to pass go on."""
    commands = redecide_here(ctx, now)
    report_free(ctx, now)
    return commands


def redecide_here(ctx: Context, now: float) -> list[Command]:
    if ctx.mode == LOOKING and ctx.looking_now()[0] == 0:
        ctx.mode, ctx.looking = IDLE, None
        return [StopMotion()] + decide(ctx, now)
    if ctx.mode == IDLE:
        return decide(ctx, now)
    if ctx.mode != MOVING or ctx.retry_at is not None:
        return []
    ctx.lost_claims.clear()
    # Decide from the end of the edge the robot is nearer to, at the time it would get there
    # (with the fleet's auction, from the node just left): deciding from the node just left
    # while the robot was nearly at the other end turned it back and forth as requests came.
    origin, goal = ctx.node, ctx.goal_now()
    back_s, ahead_s = ctx.where_on_leg(now)
    from_goal = ahead_s < back_s and fleet_allocator(ctx) is None
    at, clock = (goal, now + ahead_s) if from_goal else (origin, now + back_s)
    decision = timed_decision(ctx, now, at, clock)
    if decision is None:
        if ctx.goal_for and fleet_allocator(ctx) is not None and \
                ctx.goal_for not in ctx.fleet_now().local:
            ctx.log.append((now, f"gave {ctx.goal_for} back to the fleet"))
            ctx.fleet_now().release()
            ctx.goal_for = 0
        return []
    problem, index, step = decision
    if ctx.fleet and not ctx.fleet.claim(int(problem.ids[index]), now,
                                         int(problem.node[index])):
        return []  # another robot took it first: drive on, the next event decides again
    ctx.waiting_for = None   # serving: idle again, it chooses its waiting place afresh
    if (step != origin) if from_goal else (step == goal):
        # a patrol's move now serves the instruction; in a fleet the move serves the one
        # the robot claimed (the one before went back to the pool)
        if not ctx.goal_for or ctx.fleet:
            ctx.goal_for, ctx.patrol_goal = int(problem.ids[index]), None
        if ctx.goal_for == int(problem.ids[index]):
            ctx.serve_at = int(problem.node[index])
        return []
    # Any other decision goes through the node just left: turn back to it mid-edge.
    ctx.patrol_goal = None
    ctx.node, ctx.goal = goal, origin
    ctx.set_off(now, ahead_s)
    ctx.goal_for, ctx.attempts = int(problem.ids[index]), 1
    ctx.serve_at = int(problem.node[index])
    ctx.log.append((now, f"turn back to {ctx.graph.names[ctx.goal]} for {ctx.goal_for}"))
    return [ctx.navigate()]


def seen_elsewhere(ctx: Context, now: float) -> list[Command]:
    """While driving to serve a person's instruction at one place, perception (or the
    introduction, which registers where it met them) put that person at another: decide
    again, which may turn the robot back mid-edge. Without this a robot that had just met the
    person it was searching for drove on to the next place of the search, and decided only
    there."""
    if not ctx.config.follow_belief or ctx.mode != MOVING or not ctx.goal_for \
            or ctx.retry_at is not None or not ctx.buffer.holds(ctx.goal_for):
        return []
    record = ctx.buffer.get(ctx.goal_for)
    target = record.instruction.target
    seen = ctx.people.now.get(target) if target and record.is_open else None
    if seen is None or seen == ctx.serve_at:
        return []
    leg = (ctx.node, ctx.goal)
    if ctx.rethought_on == leg:   # once per leg: a person seen by turns in two places (in a
        return []                 # doorway) must not turn the robot back and forth
    ctx.log.append((now, f"{target} seen at {ctx.graph.names[seen]}; decide again"))
    ctx.serve_at, ctx.rethought_on = seen, leg   # this news once, whatever the decision
    return ctx.redecide(now)


def timed_decision(ctx: Context, now: float, at: int | None = None,
                   clock: float | None = None) -> tuple[Problem, int, int | None] | None:
    """Fetch, decode and decide at node `at` (default: the robot's node) as of time `clock`
    [s] (default: now), timed (wall and thread CPU time, the latter leaving out waiting for a
    core on a loaded machine): (problem, index, next node from `at`, None: serve there), or
    None when nothing is eligible. The fleet's auction decides at the robot's node, now."""
    started, started_cpu = time.perf_counter(), time.thread_time()
    problem, available = fetch_and_decode(ctx, now)
    decision = None
    own = [k for k in available if int(problem.ids[k]) in ctx.fleet.local] if ctx.fleet else []
    if fleet_allocator(ctx) is not None and not own:
        choice = auction_choice(ctx, problem, available, now) if len(available) else None
        decision = None if choice is None else (problem, *choice)
    elif len(available):   # with the auction, the robot's own (charging) come first
        chosen = np.array(own, dtype=int) if fleet_allocator(ctx) is not None else available
        index, step = ask_planner(ctx, problem, ctx.node if at is None else at,
                                  now if clock is None else clock, chosen)
        decision = problem, index, step
    ctx.decision_s.append(time.perf_counter() - started)
    ctx.decision_cpu_s.append(time.thread_time() - started_cpu)
    return decision


def fetch_and_decode(ctx: Context, now: float) -> tuple[Problem, np.ndarray]:
    """Fig. 4-14 fetch + decode: the open instructions as a Problem, and the eligible indices.

    A searched instruction's destination is the place being searched. The planner is reset
    only when the instruction set changes, so its per-set memory (the loop guard) holds. An
    own instruction that gave way to a person waits until no person's instruction is open, and
    a person's instruction for someone the robot has never seen waits while it has a stranger
    to meet (`waiting_for_a_meeting`). Overdue instructions go first (`overdue_first`). In a
    fleet, an instruction another robot holds is not eligible, nor one this robot gave back
    (recovery.give_back) within corridor_wait_s.
    """
    pending = [r for r in ctx.buffer.open_records() if r.state == PENDING]
    if not any(r.instruction.type == HUMAN for r in pending):
        ctx.deferred.clear()
    waiting = waiting_for_a_meeting(ctx, pending)
    instructions = tuple(served_where(ctx, r.instruction, now) for r in pending)
    if ctx.config.meetings_inherit and waiting:
        instructions = meetings_inherit(ctx, pending, instructions, waiting)
    if instructions != ctx.problem_key or ctx.problem is None:
        ctx.problem = Problem(ctx.graph, instructions, ctx.config.speed_mps, ctx.node)
        ctx.problem_key = instructions
        ctx.planner.reset(ctx.problem)
    done = ctx.buffer.done_ids()  # a successor waits for its predecessor (task_buffer)
    skipped = ctx.deferred | waiting
    busy_places: Container[int] = ()
    if ctx.fleet:
        taken = ctx.taken = ctx.fleet.taken(now)
        skipped = skipped | ctx.lost_claims | taken | ctx.left_to_others(now)
        if ctx.config.one_robot_per_place:
            busy_places = ctx.fleet.busy_places(now)
    available = np.array([k for k, r in enumerate(pending)
                          if (r.instruction.previous_id == 0
                              or r.instruction.previous_id in done)
                          and r.instruction.id not in skipped
                          and instructions[k].destination not in busy_places], dtype=int)
    return ctx.problem, overdue_first(ctx, pending, instructions, available, waiting, now)


def overdue_first(ctx: Context, pending: Sequence[Record],
                  instructions: Sequence[Instruction], available: np.ndarray,
                  waiting: set[int], now: float) -> np.ndarray:
    """The eligible instructions launched at least `serve_within_s` ago, when there are any
    (with the robot's charging, which never waits), else all eligible ones. Eq. 4-2's reward
    decays so fast (β 0.94-0.98 per second) that after a few minutes an old request is worth
    next to nothing against a new one, and a reward-maximising planner would keep passing it
    over; an overdue one is served before any newer one. A meeting counts as overdue while an
    overdue request waits for it (its stranger may be that request's person), as old as that
    request. Among the overdue ones, whose rewards have decayed to next to nothing, the reward
    would again serve the newest first; instead, with `overdue_order` "smith" (the default), the
    one with the most priority per second of the robot's time goes first: Table 5-5's γ over
    the time to drive there and serve it (`instructions`: where each is served, with its
    planning priority, a meeting's inherited). This is Smith's rule (W. E. Smith, "Various
    optimizers for single-stage production", 1956), which minimises the weighted sum of
    completion times (a call for physical help elsewhere goes before a long chat here) but lets
    a long chat wait while shorter ones keep coming. With "oldest" the one launched first goes
    first (the most priority per second breaks ties): Jackson's rule (J. R. Jackson,
    "Scheduling a production line to minimize maximum tardiness", 1955), the least largest
    lateness for equal allowances (`scripts/bench_overdue` measures both). The charge never
    competes. While a person's request is eligible the robot's own instructions are not
    overdue, meetings excepted (§4.2.1: the robot serves itself only when no person needs it;
    `own_yields`). With the fleet's auction every overdue one stays: the auction gives each to a
    robot, and a robot kept to one would leave the one given to it waiting."""
    limit = ctx.config.serve_within_s
    if limit <= 0 or not len(available):
        return available
    waited_since = min((r.instruction.start_time for r in pending
                        if r.instruction.id in waiting), default=math.inf)

    def launched(k: int) -> float:
        instruction = pending[k].instruction
        if is_meeting(ctx.functions, instruction):
            return min(instruction.start_time, waited_since)
        return instruction.start_time

    charge = ctx.charging.function_code if ctx.charging is not None else None
    charges = [k for k in available if pending[k].instruction.function == charge]
    overdue = [k for k in available if now - launched(k) >= limit and k not in charges]
    if any(pending[k].instruction.type == HUMAN for k in available):
        # the robot's own (a reminder, a recommendation) never go before a person's request
        overdue = [k for k in overdue if pending[k].instruction.type == HUMAN
                   or is_meeting(ctx.functions, pending[k].instruction)]
    if not overdue:   # an overdue charge alone goes first
        late = [k for k in charges if now - launched(k) >= limit]
        return np.array(late, dtype=int) if late else available
    if fleet_allocator(ctx) is None:   # the fleet's auction orders them over its robots
        def priority_per_s(k: int) -> tuple[float, float]:
            instruction = instructions[k]
            cost_s = travel_s(ctx, ctx.node, instruction.destination) + instruction.duration
            return instruction.gamma / max(cost_s, 1.0), -launched(k)   # ties: the oldest
        if ctx.config.overdue_order == "oldest":
            overdue = [min(overdue, key=lambda k: (launched(k), -priority_per_s(k)[0]))]
        else:
            overdue = [max(overdue, key=priority_per_s)]
    return np.array([k for k in available if k in charges or k in overdue], dtype=int)


def meetings_inherit(ctx: Context, pending: Sequence[Record],
                     instructions: tuple[Instruction, ...],
                     waiting: set[int]) -> tuple[Instruction, ...]:
    """The planner's copies of the `introduce` instructions take the priority (γ, β) of the
    strongest person's request that waits for a meeting, when it is higher than their own: the
    stranger may be the person that request is for, so meeting them is worth that much (the
    journal keeps the meeting's own priority)."""
    strongest = max((r.instruction for r in pending if r.instruction.id in waiting),
                    key=lambda instruction: instruction.gamma)

    def inherited(instruction: Instruction) -> Instruction:
        if is_meeting(ctx.functions, instruction) and instruction.gamma < strongest.gamma:
            return replace(instruction, gamma=strongest.gamma, beta=strongest.beta)
        return instruction
    return tuple(inherited(instruction) for instruction in instructions)


def waiting_for_a_meeting(ctx: Context, pending: Sequence[Record]) -> set[int]:
    """Ids of the people's instructions that wait for a meeting while an `introduce` instruction
    is pending: their person has never been seen (not met yet, so the camera cannot tell who
    they are; thesis 000 §3.2.3), or was not where the robot looked and has not been seen
    anywhere since (they may have changed clothes). The stranger the robot is to meet may be
    them; once perception sees them again (met, recalled in new clothes), their request goes on."""
    meeting = any(is_meeting(ctx.functions, r.instruction) for r in pending)
    if not meeting:
        return set()
    return {r.instruction.id for r in pending if r.instruction.type == HUMAN
            and r.instruction.target and (not ctx.people.knows(r.instruction.target)
                                          or (bool(ctx.searched.get(r.instruction.id))
                                              and ctx.people.now.get(r.instruction.target)
                                              is None))}


def ask_planner(ctx: Context, problem: Problem, node: int, now: float,
                available: np.ndarray) -> tuple[int, int | None]:
    """(instruction index, next node), next node None when the decision is to serve here."""
    if ctx.node_planner:  # node planner (the seed's, Algorithm 4-2)
        action, value = cast(NodePlanner, ctx.planner).decide(node, now, available)
        if action == "serve":
            return int(value), None
        return heading(problem, node, value, available), int(value)
    # Target planner: ask once per target; keep driving to it until the set changes.
    kept = ctx.target
    if kept is not None and kept[0] is problem and kept[1] in available:
        index = kept[1]
    else:
        index = int(cast(TargetPlanner, ctx.planner).choose(node, now, available))
        ctx.target = (problem, index)
    if problem.node[index] == node:
        return index, None
    return index, int(problem.graph.next_hop[node, problem.node[index]])


def heading(problem: Problem, node: int, neighbour: int, available: np.ndarray) -> int:
    """The instruction a node planner's move serves: strongest Eq. 4-2 term through it."""
    nodes = problem.node[available]
    through = available[problem.graph.next_hop[node, nodes] == neighbour]
    candidates = through if len(through) else available
    travel_s = problem.travel_s[node, problem.node[candidates]]
    terms = problem.gamma[candidates] * np.power(problem.beta[candidates], travel_s)
    return int(candidates[int(np.argmax(terms))])


class Deciding(Leaf):
    """An idle robot asks the planner: serve here, drive on, or patrol."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("decide: serve, drive or patrol", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.mode != IDLE:
            return Status.FAILURE
        ctx.out += decide(ctx, ctx.now)
        return Status.SUCCESS
