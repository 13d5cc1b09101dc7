"""A robot of a fleet (ROS-free): at every event it first sends the commands an earlier event
owes and rejoins the fleet when due (its first event, after a fault or a failed pool write); at
every tick it takes in what the other robots received, closes what the pool holds closed,
renews its lease and reports where and when it will be free next (for the fleet's auction). A
robot on its own (no fleet) skips all of this.
"""
from py_trees.common import Status

from task_planner.behaviours.context import ABORTED, ARRIVED, Context, Leaf
from task_planner.behaviours.dropping import drop
from task_planner.behaviours.fleet_allocation import report_free
from task_planner.behaviours.receiving import react
from task_planner.behaviours.recovery import fault
from task_planner.behaviours.searching import where
from task_planner.executor_commands import MOVING, Command
from task_planner.instruction import ROBOT
from task_planner.task_buffer import Record


def fleet_sync(ctx: Context, now: float) -> list[Command]:
    """The commands an earlier event owes (it raised after ordering them), and those of a
    rejoin when one is due."""
    if ctx.fleet is None:
        return []
    commands, ctx.owed = ctx.owed, []
    return commands + rejoin_fleet(ctx, now)


def rejoin_fleet(ctx: Context, now: float) -> list[Command]:
    """After a start, a fault or a failed pool write: FleetLink.rejoin from the journal,
    claiming again the instruction the robot serves, where it serves it (its charging
    instructions stay its own), and hold again, one by one, the corridors it stands in or
    drives into. An open instruction whose id the fleet knows as another instruction fails
    here with the reason (serving it would serve the other: the robot stops); one another
    robot took meanwhile the robot stops serving and leaves open. Returns the commands."""
    if ctx.in_fleet:
        return []
    fleet = ctx.fleet_now()
    charge = ctx.charging.function_code if ctx.charging else None
    serving = ctx.serving()
    place = where(ctx, ctx.buffer.get(serving).instruction) if serving else -1
    clashes = fleet.rejoin(ctx.buffer.records(), lambda instruction: (
        instruction.type == ROBOT and instruction.function == charge),
        keep=serving, now=now, place=place)
    ctx.in_fleet = True
    commands = []
    if serving in clashes:
        commands = fault(ctx, now, clashes[serving], fail_it=False)
    elif serving and fleet.held != serving and serving not in fleet.local:
        ctx.log.append((now, f"lost {serving} to another robot"))
        commands = fault(ctx, now, f"instruction {serving} is another robot's now",
                         fail_it=False)
    for instruction_id, reason in clashes.items():
        if ctx.buffer.get(instruction_id).is_open:
            ctx.buffer.fail(instruction_id, now, f"not served: {reason}")
            ctx.log.append((now, f"failed {instruction_id}: {reason}"))
    here = ctx.corridors_of((ctx.node,))
    ahead = ctx.corridors_of((ctx.goal,)) - here if ctx.mode == MOVING else set()
    for name in sorted(here) + sorted(ahead):   # one by one: each is held or not
        fleet.enter({name}, now)   # "" or another robot came in meanwhile: it leaves
    return commands


def fleet_news(ctx: Context, now: float) -> list[Command]:
    """Take in what the other robots received, close what the pool holds closed, then
    decide on the news; renew the lease and report where the robot will be free."""
    if ctx.fleet is None:
        return []
    commands = []
    news = [i for i in ctx.fleet.news() if not ctx.buffer.holds(i.id)]
    results = ctx.buffer.submit_many(news, now) if news else []
    open_ids = [r.instruction.id for r in ctx.buffer.open_records()]
    for instruction_id, state, reason in ctx.fleet.closed_in_pool(open_ids):
        if ctx.buffer.get(instruction_id).is_open:   # not closed with its predecessor
            def close(i: int, t: float, why: str, s: int = state) -> Record:
                return ctx.buffer.close_elsewhere(i, t, s, why)
            commands += drop(ctx, instruction_id, now, reason, close)
    if results:
        commands += react(ctx, results, now)
    ctx.fleet.renew(now)
    report_free(ctx, now, fresh=False)
    return commands


class FleetSync(Leaf):
    """Owed commands and a due rejoin, at every event. An arrival or an abort is not handled
    when the rejoin stopped the robot (what it drove for is no longer its own)."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("fleet: owed commands, rejoin", ctx)

    def step(self, ctx: Context) -> Status:
        ctx.synced = fleet_sync(ctx, ctx.now)
        ctx.out += ctx.synced
        if ctx.synced and ctx.event in (ARRIVED, ABORTED):
            return Status.FAILURE
        return Status.SUCCESS
