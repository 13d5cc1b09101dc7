"""Recovery (ROS-free): after a navigation abort the robot asks to pass, waits and retries the
goal (`max_goal_attempts` in all), then fails the instruction the move was for and decides again.
In a fleet, while another robot stands at the goal (a room that fits one robot), it waits for it
to leave, at most `corridor_wait_s`; then it gives an instruction of the pool back to the fleet
(another robot may reach its place, or this one after `corridor_wait_s`), at most
`max_handbacks` times, before it fails it. A fault in a step fails the instruction being served
(journalled, so a restart never re-runs it) and stops the robot.
"""
from py_trees.common import Status

from task_planner.behaviours.context import ABORTED, Context, Leaf
from task_planner.behaviours.looking import look_step
from task_planner.behaviours.serving import fail
from task_planner.executor_commands import IDLE, LOOKING, MOVING, Command, Say, StopMotion, Wait
from task_planner.task_buffer import ACTIVE


def recover(ctx: Context, now: float, reason: str) -> list[Command]:
    """Navigation gave up on the goal: ask to pass and retry it, then fail the instruction
    it was for (a turn of a look around is skipped)."""
    if ctx.mode == LOOKING:
        return look_step(ctx, now)
    if ctx.mode != MOVING:
        raise RuntimeError(f"abort reported while {ctx.mode}")
    if ctx.attempts < ctx.config.max_goal_attempts:
        ctx.attempts += 1
        ctx.log.append((now, f"retry {ctx.attempts} to {ctx.graph.names[ctx.goal_now()]}"))
        if ctx.config.pass_wait_s > 0:  # perhaps someone stands in the way
            ctx.retry_at = now + ctx.config.pass_wait_s
            return [Say(ctx.config.pass_request), Wait(ctx.retry_at)]
        return [ctx.navigate()]
    waiting = wait_for_robot_in_the_way(ctx, now)
    if waiting:
        return waiting
    goal, ctx.mode, ctx.goal = ctx.goal_now(), IDLE, None
    if not ctx.goal_for and ctx.patrol_goal is not None:  # patrol elsewhere for now
        ctx.looked_s[ctx.patrol_goal], ctx.patrol_goal = now, None
    if not ctx.goal_for and ctx.waiting_for is not None:   # a waiting place out of reach:
        ctx.waiting_for, ctx.wait_given_up = None, (goal, now)   # matched afresh, not via goal
    if ctx.goal_for and ctx.buffer.get(ctx.goal_for).is_open:
        why = (f"navigation to {ctx.graph.names[goal]} aborted "
               f"{ctx.config.max_goal_attempts} times: {reason}")
        if not give_back(ctx, ctx.goal_for, now, why):
            fail(ctx, ctx.goal_for, now, why)
    return ctx.decide(now)


def give_back(ctx: Context, instruction_id: int, now: float, why: str) -> bool:
    """In a fleet, give an instruction of the pool whose place the robot cannot reach back to
    the fleet, at most `max_handbacks` times -> True; False (it fails instead) alone, for the
    robot's own instructions, or when the hand-backs are spent. A request whose place another
    robot blocks is then served by the other robot, or by this one a minute later, instead of
    failing."""
    if ctx.fleet is None or instruction_id in ctx.fleet.local:
        return False
    _, times = ctx.given_back.get(instruction_id, (now, 0))
    if times >= ctx.config.max_handbacks:
        return False
    ctx.given_back[instruction_id] = (now, times + 1)
    ctx.fleet.release()
    if ctx.buffer.get(instruction_id).state == ACTIVE:
        ctx.buffer.requeue(instruction_id)
    ctx.log.append((now, f"give {instruction_id} back to the fleet ({times + 1} of "
                         f"{ctx.config.max_handbacks}): {why}"))
    return True


def robot_in_the_way(ctx: Context, goal: int, now: float) -> str | None:
    """Another robot of the fleet that reported itself at `goal` (standing there, or to be free
    there), or None."""
    if ctx.fleet is None:
        return None
    link = ctx.fleet_now()
    return next((name for name, (node, _) in sorted(link.fleet(now).items())
                 if name != link.robot and node == goal), None)


def wait_for_robot_in_the_way(ctx: Context, now: float) -> list[Command]:
    """The retries are spent, but another robot stands at the goal: wait for it to leave and
    retry, at most `corridor_wait_s` from the first such wait for this goal; [] when no robot
    is in the way or the wait is over. Two robots of the household fleet in one small room
    block each other's paths, and a person's request failed that way."""
    goal = ctx.goal_now()
    other = robot_in_the_way(ctx, goal, now)
    if other is None:
        return []
    if ctx.blocked is None or ctx.blocked[0] != goal or \
            now - ctx.blocked[1] > 2 * ctx.config.corridor_wait_s:   # an old wait: a new one
        ctx.blocked = (goal, now)
    if now - ctx.blocked[1] >= ctx.config.corridor_wait_s:
        return []
    ctx.retry_at = now + max(ctx.config.pass_wait_s, ctx.config.corridor_poll_s)
    ctx.log.append((now, f"wait: {other} is at {ctx.graph.names[goal]}; retry then"))
    return [Wait(ctx.retry_at)]


def fault(ctx: Context, now: float, reason: str, fail_it: bool = True,
          rejoin: bool = False) -> list[Command]:
    """A step of the executor raised: fail the instruction being served with `reason`, stop,
    and go idle. With `fail_it` off (another robot of the fleet holds it now, or the fleet pool
    cannot be reached) it is left open, not failed; with `rejoin` the robot rejoins the fleet at
    the next event (the pool was lost: its claims may have lapsed meanwhile). Returns the
    commands; the next tick decides afresh."""
    instruction_id = ctx.serving()
    ctx.mode, ctx.goal, ctx.goal_for, ctx.attempts = IDLE, None, 0, 0
    ctx.executing = ctx.verifying = ctx.looking = ctx.retry_at = None
    ctx.corridor_wait = None
    ctx.patrol_goal = ctx.target = None
    ctx.problem_key = ctx.problem = None
    commands: list[Command] = [StopMotion()]
    if rejoin:
        ctx.in_fleet = False
    if not fail_it:
        if instruction_id and ctx.buffer.get(instruction_id).state == ACTIVE:
            ctx.buffer.requeue(instruction_id)   # its function was cut short here
        ctx.log.append((now, f"stop: {reason}"))
        return commands
    ctx.in_fleet = False   # a pool write may have failed: the next event rejoins
    if instruction_id and ctx.buffer.get(instruction_id).is_open:
        commands += fail(ctx, instruction_id, now, f"fault while serving it: {reason}")
    else:
        ctx.log.append((now, f"fault: {reason}"))
    return commands


class Recovering(Leaf):
    """Navigation gave up on its goal (an ABORTED event): retry, or fail and decide again."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("recover: ask to pass, retry, fail", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.event != ABORTED:
            return Status.FAILURE
        ctx.out += recover(ctx, ctx.now, ctx.reason)
        return Status.SUCCESS
