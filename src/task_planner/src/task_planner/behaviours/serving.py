"""Serving an instruction once the robot is at its place and its person is there (ROS-free):
start the robot function (PENDING -> ACTIVE), finish it when its time is up (write back, thesis
000 Fig. 4-14), or fail it with the reason; successors whose predecessor never arrived fail too.
"""
from py_trees.common import Status

from task_planner import fleet_pool
from task_planner.behaviours.charging import save_battery
from task_planner.behaviours.context import Leaf, still_busy
from task_planner.executor_commands import EXECUTING, IDLE, Execute, Say, Search

def close_in_fleet(ctx, instruction_id, now, state):
    """Close an instruction in the fleet's pool too (a robot of a fleet)."""
    if ctx.fleet is not None:
        trouble = ctx.fleet.close(instruction_id, now, state)
        if trouble:
            ctx.log.append((now, f"fleet: {trouble}"))


def fail(ctx, instruction_id, now, reason):
    """Journal the instruction FAILED with `reason`; the robot says it could not complete it."""
    ctx.buffer.fail(instruction_id, now, reason)
    close_in_fleet(ctx, instruction_id, now, fleet_pool.FAILED)
    ctx.search.pop(instruction_id, None)
    ctx.searched.pop(instruction_id, None)
    ctx.log.append((now, f"failed {instruction_id}: {reason}"))
    return [Say(f"Sorry, I could not complete request {instruction_id}.")]


def end_search(ctx, instruction, now, found):
    """Keep a finished search (one that missed the person at least once) for the report."""
    places = ctx.searched.get(instruction.id)
    if not places:
        return
    names = [ctx.graph.names[n] for n in places]
    ctx.buffer.store_search(Search(
        instruction.id, instruction.target, ctx.search_start.pop(instruction.id, now), now,
        found, tuple(names + [ctx.graph.names[ctx.node]] if found else names)))


def execute(ctx, instruction, function, now):
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


def finish(ctx, now):
    """The executing function's time is up: journal it DONE with its reward (a charge fills
    the battery) and go idle."""
    instruction_id = ctx.executing[0]
    record = ctx.buffer.finish(instruction_id, now)
    close_in_fleet(ctx, instruction_id, now, fleet_pool.DONE)
    if ctx.charging and record.instruction.function == ctx.charging.function_code:
        ctx.charging.battery.charge(record.instruction.duration)
        save_battery(ctx, force=True)
    ctx.search.pop(instruction_id, None)
    ctx.searched.pop(instruction_id, None)
    ctx.log.append((now, f"done {instruction_id}: reward {record.reward_earned:.3f}"))
    ctx.mode, ctx.executing = IDLE, None


def give_up_waiting(ctx, now):
    """Fail successors whose predecessor never arrived (BufferConfig.predecessor_wait_s)."""
    commands = []
    for record in ctx.buffer.fail_missing_predecessors(now):
        ctx.log.append((now, f"failed {record.instruction.id}: {record.reason}"))
        commands.append(Say(f"Sorry, I could not complete request {record.instruction.id}."))
    return commands


class Executing(Leaf):
    """While a robot function runs: finish it when its time is up."""

    def __init__(self, ctx):
        super().__init__("execute", ctx)

    def step(self, ctx):
        if ctx.mode != EXECUTING:
            return Status.FAILURE
        if ctx.now >= ctx.executing[1]:
            finish(ctx, ctx.now)
        return still_busy(ctx, EXECUTING)
