"""Where the robot's time goes (ROS-free): what it is doing now, as one label of a small set, so
a run can be broken down into travel, looking around, dialogue, robot functions, waiting for a
clear path, searching, patrol, charging and idle time."""
from collections.abc import Sequence
from typing import Any

from task_planner.behaviours.context import Context
from task_planner.executor_commands import EXECUTING, LOOKING, MOVING, VERIFYING

TRAVEL, LOOK_AROUND, SEARCHING, WAITING = "travel", "look around", "searching", "waiting"
DIALOGUE, FUNCTION, CHARGING, PATROL, IDLE = "dialogue", "function", "charging", "patrol", "idle"
ACTIVITIES = (TRAVEL, LOOK_AROUND, SEARCHING, WAITING, DIALOGUE, FUNCTION, CHARGING, PATROL,
              IDLE)
DIALOGUE_FUNCTIONS = ("introduce",)   # robot functions that are a conversation


def activity(ctx: Context) -> str:
    """What the robot does now: waiting (after an abort it asked to pass, or for a corridor),
    searching (moving or looking for a person after the first place missed them), look around
    (at an instruction's place, before any miss), travel (to an instruction's place), dialogue,
    charging or another robot function, patrol (moving or looking without an instruction), or
    idle."""
    if ctx.mode == MOVING:
        if ctx.retry_at is not None:
            return WAITING
        if not ctx.goal_for:
            return PATROL
        return SEARCHING if ctx.searched.get(ctx.goal_for) else TRAVEL
    if ctx.mode in (LOOKING, VERIFYING):
        instruction_id = (ctx.looking_now()[0] if ctx.mode == LOOKING
                          else ctx.verifying_now()[0])
        if not instruction_id:
            return PATROL
        return SEARCHING if ctx.searched.get(instruction_id) else LOOK_AROUND
    if ctx.mode == EXECUTING:
        instruction = ctx.buffer.get(ctx.executing_now()[0]).instruction
        if ctx.charging and instruction.function == ctx.charging.function_code:
            return CHARGING
        function = ctx.functions.get(instruction.function)
        name = function.name if function else ""
        if name == "charge":
            return CHARGING
        return DIALOGUE if name in DIALOGUE_FUNCTIONS else FUNCTION
    return IDLE


def time_shares(changes: Sequence[Sequence[Any]], start_s: float, end_s: float) -> dict[str, float]:
    """{activity: seconds} over [start_s, end_s] of a [[t, activity], ...] change list (each
    activity lasts until the next change); the time before the first change is not counted."""
    seconds: dict[str, float] = {}
    for k, (t, label) in enumerate(changes):
        until = changes[k + 1][0] if k + 1 < len(changes) else end_s
        lo, hi = max(t, start_s), min(until, end_s)
        if hi > lo:
            seconds[label] = seconds.get(label, 0.0) + hi - lo
    return seconds
