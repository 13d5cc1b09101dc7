"""Patrol (ROS-free): an idle robot drives to the stalest, likeliest occupied place and looks
around it (thesis 000 §4.2.1: the robot wanders and observes the household when unoccupied)."""
from task_planner.behaviours.looking import start_look
from task_planner.behaviours.context import Context
from task_planner.executor_commands import MOVING, Command, Navigate
from task_planner.people_belief import patrol_target


def patrol(ctx: Context, now: float) -> list[Command]:
    """Idle: drive to the stalest, likeliest occupied place and look around it."""
    target = patrol_target(range(ctx.graph.size), ctx.people, ctx.looked_s, now,
                           ctx.config.patrol_interval_s, ctx.graph.shortest[ctx.node],
                           ctx.config.never_looked_s)
    if target is None:
        return []
    if target == ctx.node:
        return start_look(ctx, 0, now)
    step = int(ctx.graph.next_hop[ctx.node, target])
    if ctx.patrol_goal != target:
        ctx.log.append((now, f"patrol to {ctx.graph.names[target]}"))
    ctx.patrol_goal = target
    ctx.mode, ctx.goal, ctx.goal_for, ctx.attempts = MOVING, step, 0, 1
    return [Navigate(step, 0)]
