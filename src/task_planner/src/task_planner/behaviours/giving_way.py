"""Giving way (ROS-free): a person's request interrupts what the robot does for an instruction
it gave itself; the interrupted instruction waits until no person's instruction is open."""
from task_planner.behaviours.context import Context
from task_planner.executor_commands import EXECUTING, IDLE, LOOKING, Command, Say, StopMotion
from task_planner.instruction import ROBOT


def yield_own(ctx: Context, now: float) -> list[Command]:
    """With `own_yields`, a person's request interrupts what the robot does for an
    instruction it gave itself (unless its function is in `own_kept`): back to pending,
    served later."""
    if not ctx.config.own_yields or ctx.mode not in (EXECUTING, LOOKING):
        return []
    instruction_id = (ctx.executing_now()[0] if ctx.mode == EXECUTING
                      else ctx.looking_now()[0])
    if not instruction_id:
        return []
    instruction = ctx.buffer.get(instruction_id).instruction
    function = ctx.functions.get(instruction.function)
    if instruction.type != ROBOT or function is None or function.name in ctx.config.own_kept:
        return []
    if ctx.mode == EXECUTING:
        ctx.buffer.requeue(instruction_id)
    ctx.deferred.add(instruction_id)
    ctx.mode, ctx.executing, ctx.looking = IDLE, None, None
    ctx.log.append((now, f"{instruction_id} waits: a person asked for something"))
    return [StopMotion(), Say(ctx.config.yield_notice)]
