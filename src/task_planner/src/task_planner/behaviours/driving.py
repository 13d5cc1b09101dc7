"""Driving along the graph (ROS-free): a move goes out once the robot holds the corridor it
drives into (in a fleet; it waits while another robot is in it, at most corridor_wait_s), and an
arrival ends the move: a patrol looks around its place, anything else decides again.
"""
from py_trees.common import Status

from task_planner.behaviours.charging import check_battery
from task_planner.behaviours.context import ARRIVED, Context, Leaf, still_busy
from task_planner.behaviours.looking import look_step, start_look
from task_planner.executor_commands import IDLE, LOOKING, MOVING, Command, Wait


def drive(ctx: Context, now: float) -> list[Command]:
    """Navigate to the goal, once the robot holds the corridor it drives into (in a fleet);
    while another robot is in it, wait and look again, at most corridor_wait_s. A robot
    never waits for the corridor it stands in."""
    here = ctx.corridors_of((ctx.node,)) if ctx.fleet else set()
    needed = ctx.corridors_of((ctx.goal,)) - here if ctx.fleet else set()
    holder = ctx.fleet_now().enter(needed, now) if needed else ""
    if here:
        ctx.fleet_now().enter(here, now)   # kept while it leaves (unless another robot has it)
    if holder:
        since = ctx.corridor_wait if ctx.corridor_wait is not None else now
        if now - since < ctx.config.corridor_wait_s:
            if ctx.corridor_wait is None:
                ctx.log.append((now, f"wait: {holder} is in {', '.join(sorted(needed))}"))
            ctx.corridor_wait = since
            ctx.retry_at = now + ctx.config.corridor_poll_s
            return [Wait(ctx.retry_at)]
        ctx.log.append((now, f"drive on after {now - since:.0f} s: {holder} stays in "
                             f"{', '.join(sorted(needed))}"))
    ctx.corridor_wait = None
    return [ctx.navigate()]


def arrive(ctx: Context, now: float) -> list[Command]:
    """The navigation goal was reached (or, while looking around, the heading)."""
    if ctx.mode == LOOKING:
        return look_step(ctx, now)
    if ctx.mode != MOVING:
        raise RuntimeError(f"arrival reported while {ctx.mode}")
    ctx.node, ctx.mode, ctx.goal = ctx.goal_now(), IDLE, None
    ctx.log.append((now, f"at {ctx.graph.names[ctx.node]}"))
    if ctx.fleet:   # out of a corridor once the robot stands outside it
        ctx.fleet.leave(keep=ctx.corridors_of((ctx.node,)))
    commands = check_battery(ctx, now)
    if ctx.mode == IDLE and ctx.goal_for == 0 and ctx.patrol_goal == ctx.node:
        return commands + start_look(ctx, 0, now)
    return commands + (ctx.decide(now) if ctx.mode == IDLE else [])


class Driving(Leaf):
    """While driving: after a wait (asked to pass, corridor taken) send the goal again."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("drive", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.mode != MOVING:
            return Status.FAILURE
        if ctx.retry_at is not None and ctx.now >= ctx.retry_at:
            ctx.retry_at = None
            ctx.out += drive(ctx, ctx.now)
        return still_busy(ctx, MOVING)


class Arriving(Leaf):
    """Navigation reached its goal (an ARRIVED event)."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("arrive", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.event != ARRIVED:
            return Status.FAILURE
        ctx.out += arrive(ctx, ctx.now)
        return Status.SUCCESS
