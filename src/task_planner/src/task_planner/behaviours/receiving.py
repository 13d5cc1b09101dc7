"""Taking in new instructions (ROS-free): journal them in one transaction (in a fleet: checked
against and shared with the pool under its write lock), then react: a person's request
interrupts the robot's own instruction (giving_way), and the robot decides again. New
instructions from outside beyond `ExecutorConfig.max_open` open ones are refused with the reason
(every open instruction costs each decision and each state message); the robot's own charge
instruction and what other robots of its fleet took are not capped.
"""
from collections.abc import Iterable, Mapping, Sequence

from py_trees.common import Status

from task_planner.behaviours.context import RECEIVED, Context, Leaf
from task_planner.behaviours.giving_way import yield_own
from task_planner.executor_commands import Command
from task_planner.instruction import HUMAN, Instruction
from task_planner.task_buffer import ACTIVE, PENDING, Record


def new_id(ctx: Context, previous_id: int = 0) -> int:
    """The id for an instruction whose sender lets the robot choose (its fleet's, if any)."""
    own = ctx.buffer.next_id(previous_id)
    return ctx.fleet.next_id(own - 1) if ctx.fleet else own


def beyond_cap(ctx: Context, instructions: Sequence[Instruction]) -> dict[int, str]:
    """{id: reason} for the new instructions beyond `max_open` open ones (0: no cap); one the
    buffer already holds is no new one (a re-submission answers with its record)."""
    cap = ctx.config.max_open
    if not cap:
        return {}
    counts = ctx.buffer.counts()
    open_after = counts[PENDING] + counts[ACTIVE]   # with the ones of `instructions` taken
    refused = {}
    for instruction in instructions:
        if ctx.buffer.holds(instruction.id) or instruction.id in refused:
            continue
        if open_after < cap:
            open_after += 1
        else:
            refused[instruction.id] = (f"instruction {instruction.id}: the task buffer is full: "
                                       f"{open_after} open instruction{'s' * (open_after != 1)} "
                                       f"(at most {cap})")
    return refused


def journal(ctx: Context, instructions: Sequence[Instruction], now: float,
            capped: bool = False) -> list[tuple[Record | None, str]]:
    """Journal `instructions` (one transaction; in a fleet also shared with the pool, an id
    the pool holds for another instruction refused before it is journalled; `capped`: those
    beyond the cap refused): a (record, error) per instruction."""
    full = beyond_cap(ctx, instructions) if capped else {}
    if ctx.fleet is None:
        return journal_all_but(ctx, instructions, full, now)
    # under the pool's write lock from the id check to the share
    with ctx.fleet.transaction():
        results = journal_all_but(ctx, instructions, {**ctx.fleet.conflicts(instructions),
                                                      **full}, now)
        ctx.fleet.share([record.instruction for record, _ in results if record])
    return results


def journal_all_but(ctx: Context, instructions: Sequence[Instruction], refused: Mapping[int, str],
                    now: float) -> list[tuple[Record | None, str]]:
    """Journal the instructions whose id is not in `refused` ({id: reason}): a (record,
    error) per instruction, in order."""
    taken = [i for i in instructions if i.id not in refused]
    journalled = iter(ctx.buffer.submit_many(taken, now) if taken else ())
    return [(None, refused[i.id]) if i.id in refused else next(journalled)
            for i in instructions]


def react(ctx: Context, results: Sequence[tuple[Record | None, str]], now: float) -> list[Command]:
    """Log what was journalled or refused; a person's request interrupts the robot's own
    instruction; decide again. Returns the commands."""
    for record, error in results:
        ctx.log.append((now, f"refused: {error}" if error or record is None else
                        f"received {record.instruction.id}"))
    if not any(record is not None for record, _ in results):
        return []
    from_people = any(r is not None and r.instruction.type == HUMAN for r, _ in results)
    commands = yield_own(ctx, now) if from_people else []
    return commands + ctx.redecide(now)


def take_in(ctx: Context, instructions: Sequence[Instruction], now: float,
            owed: Iterable[Command] = (),
            capped: bool = False) -> tuple[list[tuple[Record | None, str]], list[Command]]:
    """Journal (`capped`: see journal) and react (claims as at a tick, each committed after the
    pool transaction); returns (results, commands). When the journal write raises, the robot
    rejoins the fleet at its next event, and `owed` (commands already ordered) go out with it."""
    try:
        results = journal(ctx, instructions, now, capped)
    except Exception:
        if ctx.fleet is not None:
            ctx.in_fleet = False   # rolled back: the next event rejoins from the journal
            ctx.owed = list(owed)  # the rejoin's stop goes out with the next tick
        raise
    return results, react(ctx, results, now)


class TakingIn(Leaf):
    """New instructions (a RECEIVED event): journal them and react."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("take in, give way, decide again", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.event != RECEIVED:
            return Status.FAILURE
        ctx.results, commands = take_in(ctx, ctx.inbox, ctx.now, owed=ctx.synced, capped=True)
        ctx.out += commands
        return Status.SUCCESS
