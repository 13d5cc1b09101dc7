"""Dropping an instruction (ROS-free): one closed by a cancel request (for the whole fleet) or
closed by another robot of the fleet; the robot stops serving it and decides again."""
from collections.abc import Callable

from py_trees.common import Status

from task_planner import fleet_pool
from task_planner.behaviours.context import CANCELLED, Context, Leaf
from task_planner.behaviours.serving import close_in_fleet
from task_planner.executor_commands import EXECUTING, IDLE, LOOKING, VERIFYING, Command, \
    StopMotion
from task_planner.task_buffer import Record


def drop(ctx: Context, instruction_id: int, now: float, reason: str,
         close: Callable[[int, float, str], object]) -> list[Command]:
    """Close an open instruction with `close(id, now, reason)` and stop serving it."""
    close(instruction_id, now, reason)
    if ctx.mode == EXECUTING and ctx.executing_now()[0] == instruction_id:
        ctx.mode, ctx.executing = IDLE, None
    if ctx.mode == VERIFYING and ctx.verifying_now()[0] == instruction_id:
        ctx.mode, ctx.verifying = IDLE, None
    stop: list[Command] = []
    if ctx.mode == LOOKING and ctx.looking_now()[0] == instruction_id:
        ctx.mode, ctx.looking, stop = IDLE, None, [StopMotion()]
    ctx.search.pop(instruction_id, None)
    ctx.searched.pop(instruction_id, None)
    ctx.log.append((now, f"closed {instruction_id}: {reason}"))
    return stop + ctx.redecide(now)


def cancel(ctx: Context, record: Record, now: float) -> list[Command]:
    """Withdraw the instruction of `record` (read before the event's fleet rejoin) for the
    whole fleet: closed in the pool first, so deciding anew gives back what the robot held and
    no other robot claims it meanwhile; the robot stops its function if it was executing it."""
    instruction_id = record.instruction.id
    if record.is_open:   # else buffer.cancel below refuses it
        close_in_fleet(ctx, instruction_id, now, fleet_pool.CANCELLED)
    return drop(ctx, instruction_id, now, "cancelled by request",
                lambda i, t, why: ctx.buffer.cancel(i, t, why))


class Cancelling(Leaf):
    """A cancel request (a CANCELLED event)."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("cancel", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.event != CANCELLED:
            return Status.FAILURE
        if ctx.cancelled is None:
            raise RuntimeError("a cancel event without the record to withdraw")
        ctx.out += cancel(ctx, ctx.cancelled, ctx.now)
        return Status.SUCCESS
