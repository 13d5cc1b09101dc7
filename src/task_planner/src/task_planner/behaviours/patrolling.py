"""Patrol (ROS-free): an idle robot drives to the stalest, likeliest occupied place and looks
around it (thesis 000 §4.2.1: the robot wanders and observes the household when unoccupied). In a
fleet an idle robot never stays in a corridor: it would block the robots that drive through."""
from task_planner.behaviours.context import Context
from task_planner.behaviours.driving import drive
from task_planner.behaviours.looking import start_look
from task_planner.executor_commands import MOVING, Command
from task_planner.people_belief import patrol_target


def patrol(ctx: Context, now: float) -> list[Command]:
    """Idle: drive to the stalest, likeliest occupied place and look around it (in a fleet, a
    place that is no corridor; a place people only pass through, `pass_through`, only while
    someone is expected there)."""
    corridors = fleet_corridors(ctx)
    places = [n for n in range(ctx.graph.size) if n not in corridors
              and (n not in ctx.config.pass_through or ctx.people.expected_at(n))]
    target = patrol_target(places, ctx.people,
                           ctx.looked_s, now, ctx.config.patrol_interval_s,
                           ctx.graph.shortest[ctx.node], ctx.config.never_looked_s)
    if target is None:
        return []
    if target == ctx.node:
        return start_look(ctx, 0, now)
    return drive_idle(ctx, target, f"patrol to {ctx.graph.names[target]}", now)


def clear_corridor(ctx: Context, now: float) -> list[Command]:
    """Idle in a fleet with nothing to look at: leave the corridor the robot stands in for the
    nearest place that is none (there it looks around)."""
    corridors = fleet_corridors(ctx)
    if ctx.node not in corridors:
        return []
    outside = [n for n in range(ctx.graph.size) if n not in corridors]
    if not outside:
        return []
    target = min(outside, key=lambda n: (ctx.graph.shortest[ctx.node][n], n))
    return drive_idle(ctx, target, f"clear the corridor {ctx.graph.names[ctx.node]} for "
                                   f"{ctx.graph.names[target]}", now)


def fleet_corridors(ctx: Context) -> tuple[int, ...]:
    """The graph nodes one robot at a time drives through, in a fleet (none alone)."""
    return tuple(ctx.config.corridors) if ctx.fleet else ()


def drive_idle(ctx: Context, target: int, why: str, now: float) -> list[Command]:
    """Drive towards `target` with no instruction (a patrol's move: looks around on arrival),
    once the robot holds the corridor it drives into, as any move (driving.drive)."""
    step = int(ctx.graph.next_hop[ctx.node, target])
    if ctx.patrol_goal != target:
        ctx.log.append((now, why))
    ctx.patrol_goal = target
    ctx.mode, ctx.goal, ctx.goal_for, ctx.attempts = MOVING, step, 0, 1
    ctx.set_off(now)
    return drive(ctx, now)
