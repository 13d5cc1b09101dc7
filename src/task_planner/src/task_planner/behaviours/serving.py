"""Serving an instruction once the robot is at its place and its person is there (ROS-free):
start the robot function (PENDING -> ACTIVE), finish it when its time is up (write back, thesis
000 Fig. 4-14), or fail it with the reason; successors whose predecessor never arrived fail too.
"""
from py_trees.common import Status

from task_planner import fleet_pool
from task_planner.behaviours.charging import save_battery
from task_planner.behaviours.context import Context, Leaf, still_busy
from task_planner.executor_commands import EXECUTING, IDLE, Command, Execute, Say, Search
from task_planner.instruction import Instruction
from task_planner.robot_functions import RobotFunction

def close_in_fleet(ctx: Context, instruction_id: int, now: float, state: int) -> None:
    """Close an instruction in the fleet's pool too (a robot of a fleet)."""
    if ctx.fleet is not None:
        trouble = ctx.fleet.close(instruction_id, now, state)
        if trouble:
            ctx.log.append((now, f"fleet: {trouble}"))


def fail(ctx: Context, instruction_id: int, now: float, reason: str) -> list[Command]:
    """Journal the instruction FAILED with `reason`; the robot says it could not complete it."""
    ctx.buffer.fail(instruction_id, now, reason)
    close_in_fleet(ctx, instruction_id, now, fleet_pool.FAILED)
    ctx.search.pop(instruction_id, None)
    ctx.searched.pop(instruction_id, None)
    ctx.rechecked.pop(instruction_id, None)
    ctx.log.append((now, f"failed {instruction_id}: {reason}"))
    return [Say(f"Sorry, I could not complete request {instruction_id}.")]


def end_search(ctx: Context, instruction: Instruction, now: float, found: bool) -> None:
    """Keep a finished search (one that missed the person at least once) for the report."""
    places = ctx.searched.get(instruction.id)
    if not places:
        return
    names = [ctx.graph.names[n] for n in places]
    ctx.buffer.store_search(Search(
        instruction.id, instruction.target, ctx.search_start.pop(instruction.id, now), now,
        found, tuple(names + [ctx.graph.names[ctx.node]] if found else names)))


def execute(ctx: Context, instruction: Instruction, function: RobotFunction,
            now: float) -> list[Command]:
    """Start the robot function of `instruction` here (PENDING -> ACTIVE); not when the
    robot's fleet lease ran out meanwhile (another robot may serve it)."""
    instruction_id = instruction.id
    if ctx.fleet and not ctx.fleet.holds(instruction_id, now):
        ctx.lost_claims.add(instruction_id)
        ctx.log.append((now, f"lost {instruction_id} to another robot"))
        return []
    end_search(ctx, instruction, now, found=True)
    ctx.buffer.start(instruction_id, now)
    ctx.mode, ctx.executing = EXECUTING, (instruction_id, now + instruction.duration)
    place = ctx.graph.names[ctx.node]
    ctx.log.append((now, f"execute {function.name} for {instruction_id} at {place}"))
    return [Execute(instruction_id, function.name, float(instruction.duration)),
            Say(function.speech(instruction, place))]


def finish(ctx: Context, now: float) -> None:
    """The executing function's time is up: journal it DONE with its reward (a charge fills
    the battery) and go idle. The person served is believed here, as seen now: the robot
    talked with them the whole time, though perception may not have told them apart meanwhile
    (seated at a table, half hidden), and their next request here is served at once."""
    instruction_id = ctx.executing_now()[0]
    record = ctx.buffer.finish(instruction_id, now)
    close_in_fleet(ctx, instruction_id, now, fleet_pool.DONE)
    if ctx.charging and record.instruction.function == ctx.charging.function_code:
        ctx.charging.battery.charge(record.instruction.duration)
        save_battery(ctx, force=True)
    ctx.search.pop(instruction_id, None)
    ctx.searched.pop(instruction_id, None)
    ctx.rechecked.pop(instruction_id, None)
    if record.instruction.target:   # they were with the robot all along: here, seen just now
        ctx.people.seen(record.instruction.target, ctx.node, now)
    ctx.log.append((now, f"done {instruction_id}: reward {record.reward_earned:.3f}"))
    ctx.mode, ctx.executing = IDLE, None


def give_up_waiting(ctx: Context, now: float) -> list[Command]:
    """Fail successors whose predecessor never arrived (BufferConfig.predecessor_wait_s)."""
    commands: list[Command] = []
    for record in ctx.buffer.fail_missing_predecessors(now):
        ctx.log.append((now, f"failed {record.instruction.id}: {record.reason}"))
        commands.append(Say(f"Sorry, I could not complete request {record.instruction.id}."))
    return commands


class Executing(Leaf):
    """While a robot function runs: finish it when its time is up."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("execute", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.mode != EXECUTING:
            return Status.FAILURE
        if ctx.now >= ctx.executing_now()[1]:
            finish(ctx, ctx.now)
        return still_busy(ctx, EXECUTING)
