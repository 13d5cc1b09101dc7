"""The fleet allocator in the running fleet (ROS-free): a robot of a fleet whose
`fleet_allocator` is the auction (fleet_auction.SequentialAuction) decides with it, not with its
own planner alone.

Every robot reports where it will be free next and from when (`report_free`, after each decision and
at a tick that finds its mode changed): idle where it stands, now; executing, at its place when its
function ends; driving for an instruction, at that instruction's place once served; driving to its
waiting place, there; driving on its own otherwise (a patrol, a given-back claim), at the node it
drives to. At a decision (arrival, completion,
news) the robot builds the fleet's view from these reports (every live robot, itself included, in
name order: ties go to the first name), auctions the instructions no other robot holds over all of
them (those another robot holds are left out: its report says when it is free of them), and serves
the first instruction of its own plan that it may start, or waits when its plan is empty. The
others' plans are provisional: each robot re-runs the auction at its own decisions (a robot given an
instruction that it has not claimed claim_wait_s after it said it would be free is passed over). A
robot driving for an instruction the auction now gives to another robot gives it back
(deciding.redecide); one already executing keeps it (its mode is not re-decided). With the patrol
off and the allocator `auction_waiting`, a robot that is given nothing drives to its waiting place
(`wait_at_place`), as the auction's `idle` sends it in scripts/bench_fleet.
"""
from collections.abc import Sequence

import numpy as np

from task_planner.behaviours.context import Context

from task_planner.behaviours.searching import where
from task_planner.behaviours.patrolling import drive_idle, fleet_corridors
from task_planner.executor_commands import EXECUTING, MOVING, VERIFYING, Command
from task_planner.fleet import FleetView, RobotStart
from task_planner.fleet_auction import SequentialAuction
from task_planner.fleet_waiting import waiting_place_of, waiting_places
from task_planner.fleet_registry import make_allocator
from task_planner.problem import Problem


def fleet_allocator(ctx: Context) -> SequentialAuction | None:
    """The auction this robot decides with, or None (a robot on its own, or a per-robot
    allocator: its own planner on the instructions nobody holds)."""
    if ctx.fleet is None:
        return None
    if ctx.allocator is None:
        allocator = make_allocator(ctx.config.fleet_allocator)
        ctx.allocator = allocator if isinstance(allocator, SequentialAuction) else False
    return ctx.allocator or None


def free_point(ctx: Context, now: float) -> tuple[int, float]:
    """(node, time [s]) where and when this robot will be free next."""
    if ctx.mode == EXECUTING:
        return ctx.node, max(now, ctx.executing_now()[1])
    if ctx.mode == VERIFYING:
        return ctx.node, max(now, ctx.verifying_now()[1])
    if ctx.mode == MOVING:
        record = ctx.buffer.get(ctx.goal_for) if ctx.goal_for else None
        if record is None or not record.is_open:   # driving idle: to its waiting place, if any
            kept = ctx.waiting_for
            goal = kept[1] if kept is not None and ctx.patrol_goal is None else ctx.goal_now()
            return goal, now + travel_s(ctx, ctx.node, goal)
        place = where(ctx, record.instruction)
        return place, now + travel_s(ctx, ctx.node, place) + record.instruction.duration
    return ctx.node, now


def travel_s(ctx: Context, start: int, end: int) -> float:
    return float(ctx.graph.shortest[start, end]) / ctx.config.speed_mps


def report_free(ctx: Context, now: float, fresh: bool = True) -> None:
    """Tell the fleet where and when this robot will be free next (an auction's robots): anew
    when `fresh` (after a decision) or when its mode changed, else the last report again
    (FleetLink.report writes it only to renew it within the lease). A robot free already at
    the node it reported free at has nothing new to tell."""
    if fleet_allocator(ctx) is None:
        return
    last = ctx.reported
    if fresh or last is None or last[0] != ctx.mode:
        node, free_at = free_point(ctx, now)
        if last is not None and last[1] == node and max(last[2], free_at) <= now:
            free_at = last[2]
        last = ctx.reported = (ctx.mode, node, free_at)
    ctx.fleet_now().report(last[1], last[2], now)


def overdue(ctx: Context, problem: Problem, view: FleetView, plans: Sequence[Sequence[int]],
            now: float) -> list[int]:
    """The instructions the auction gives another robot that has not claimed them
    claim_wait_s after the time it first said it would be free (it cannot serve them: its
    journal lacks them, or it is stuck): this robot may take them after its own plan."""
    given = {int(problem.ids[plan[0]]): (r, view.clocks[r]) for r, plan in enumerate(plans)
             if r != view.robot and plan}
    ctx.unclaimed = {i: ctx.unclaimed.get(i, free_at) for i, (_, free_at) in given.items()}
    return [plans[r][0] for i, (r, _) in given.items()
            if now - ctx.unclaimed[i] >= ctx.config.claim_wait_s]


def auction_choice(ctx: Context, problem: Problem, available: np.ndarray,
                   now: float) -> tuple[int, int | None] | None:
    """(index, next node) of the first instruction of this robot's plan after the fleet's
    auction that it may start now (in `available`; next node None: serve here), or None: the
    auction gives it nothing it may start.

    The robot decides at its node, free now; the instructions of `problem` another robot holds
    (or took at a claim this decision) and the robot's own (kept local) are left out."""
    allocator = fleet_allocator(ctx)
    if allocator is None:
        raise RuntimeError("auction_choice: the robot decides without the fleet's auction")
    link = ctx.fleet_now()
    names, fleet = fleet_positions(ctx, now)
    skipped = ctx.taken | ctx.lost_claims | link.local   # taken: read by fetch_and_decode
    open_items = np.array([k for k, i in enumerate(problem.ids) if int(i) not in skipped],
                          dtype=int)
    view = FleetView(names.index(link.robot), [int(fleet[n][0]) for n in names],
                     [max(float(fleet[n][1]), now) for n in names], open_items, {})
    allocator.reset(problem, [RobotStart(node) for node in view.nodes])
    plans = allocator.allocate(view)
    startable = set(int(k) for k in available)
    index = next((k for k in plans[view.robot] + overdue(ctx, problem, view, plans, now)
                  if k in startable), None)
    if index is None:
        return None
    place = int(problem.node[index])
    return index, None if place == ctx.node else int(problem.graph.next_hop[ctx.node, place])


def fleet_positions(ctx: Context, now: float) -> tuple[list[str], dict]:
    """(robot names in order, {name: (node, free from [s])}) of every live robot by their
    reports, this robot where it stands, free now (as it decides; it reports after)."""
    link = ctx.fleet_now()
    fleet = link.fleet(now)
    fleet[link.robot] = (ctx.node, now)
    return sorted(fleet), fleet


def out_of_reach(ctx: Context, place: int, now: float) -> bool:
    """The way to waiting place `place` leads through the node where a drive to a waiting place
    was given up less than `corridor_wait_s` ago (recovery.recover): the robot waits where it
    is, as an instruction given back to the fleet is left that long, instead of bumping into
    whatever blocks that way again and again."""
    given_up = ctx.wait_given_up
    if given_up is None or now - given_up[1] >= ctx.config.corridor_wait_s:
        return False
    return given_up[0] in ctx.graph.path(ctx.node, place)


def wait_at_place(ctx: Context, now: float) -> list[Command]:
    """A robot of the fleet's auction with nothing to do drives to its waiting place: the live
    robots, each where its last report to the pool says it will be free (this robot too, so
    every robot matches on the same table), are matched by least travel to the k-median places
    of the graph, k the live robots, corridors left out (fleet_waiting; found once per k); []
    when it is there. The place is kept until the robot serves again, the fleet changes, its
    drive there is given up (recovery.recover; then it waits where it is while the way leads
    through where it gave up, `out_of_reach`) or another robot reports itself there: matched
    again on the way, on reports of different ages, two robots could pick one place. A
    robot that hears from no other waits one renew period of the fleet link before it decides
    alone: robots started together each see only themselves until the others' first reports."""
    allocator = fleet_allocator(ctx)
    if allocator is None or not allocator.config.wait_at_medians:
        return []
    link = ctx.fleet_now()
    fleet = link.fleet(now)
    fleet.setdefault(link.robot, (ctx.node, now))   # not reported yet: where it stands
    names = sorted(fleet)
    if len(names) > 1:
        ctx.alone_since = None
    else:
        ctx.alone_since = now if ctx.alone_since is None else ctx.alone_since
        if now - ctx.alone_since < link.renew_period_s:
            ctx.waiting_for = None
            return []
    if len(names) not in ctx.waiting_places:
        corridors = fleet_corridors(ctx)
        ctx.waiting_places[len(names)] = waiting_places(
            ctx.graph.shortest, len(names),
            candidates=[n for n in range(ctx.graph.size) if n not in corridors])
    place: int | None
    kept = ctx.waiting_for
    taken = {int(fleet[n][0]) for n in names if n != link.robot}   # where the others will be
    if kept is not None and kept[0] == tuple(names) and kept[1] not in taken:
        place = kept[1]
    else:
        # every robot is matched, a busy one where it will be free: robots deciding at nearly
        # one time each see the other free a moment later, and an idle-only match would send
        # both to the place nearest them
        nodes = [int(fleet[n][0]) for n in names]
        place = waiting_place_of(names.index(link.robot), nodes,
                                 list(range(len(names))), ctx.waiting_places[len(names)],
                                 ctx.graph.shortest)
        ctx.waiting_for = None if place is None else (tuple(names), place)
    if place is None or place == ctx.node or out_of_reach(ctx, place, now):
        return []
    commands = drive_idle(ctx, place, f"wait at {ctx.graph.names[place]}", now)
    ctx.patrol_goal = None    # no look around on arrival: decide again at each node
    return commands
