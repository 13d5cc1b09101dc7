"""Finding an instruction's person at the robot's place (ROS-free): serve when they were seen
here, else look around (turns in place while perception watches, each heading held a dwell) or
stand and look, then search on (thesis 000 §4.2.1: the robot observes the household). A look
without an instruction (0) is a patrol's. A place looked all around within `look_again_s` is not
looked around again: whoever that look saw counts as here, anyone else is searched for elsewhere.
Meeting a stranger (an `introduce` instruction, §3.2.3: "the robot will approach an unknown
person and greet"), the person looked for is anyone perception saw at the place, whole shirt
and all, but cannot tell; a look that sees nobody such gives the meeting up (the stranger walked
off).
"""
import math

from py_trees.common import Status

from task_planner.behaviours.context import Context, Leaf, still_busy
from task_planner.behaviours.searching import search_next
from task_planner.behaviours.serving import execute, fail
from task_planner.executor_commands import IDLE, LOOKING, VERIFYING, Ask, Command, Navigate, \
    StopMotion, Verify, Wait
from task_planner.instruction import Instruction
from task_planner.robot_functions import RobotFunctionError, function_for, is_meeting

FACING, ASKING, FACED = "facing", "asking", "faced"   # a look's turn toward someone
#                                                      perception cannot tell, then the question
TOLD = "told"   # perception told the person faced as someone other than the one looked for
CALLING, CALLED = "calling", "called"   # the look's end: the person called by name
MAX_FACED = 3   # people one look faces and asks at most (a crowded room, noisy positions)


def serve_here(ctx: Context, instruction_id: int, now: float) -> list[Command]:
    """Verify the target person is here, then execute the robot function (or look, search or
    fail)."""
    instruction = ctx.buffer.get(instruction_id).instruction
    try:
        function = function_for(ctx.functions, instruction)
    except RobotFunctionError as error:
        return fail(ctx, instruction_id, now, str(error))
    target = instruction.target
    swept = recent_sweep(ctx, now)
    if is_meeting(ctx.functions, instruction) and ctx.config.stranger_fresh_s > 0:
        return meet_here(ctx, instruction, swept, now)
    since = now - ctx.config.fresh_s if swept is None else min(now - ctx.config.fresh_s, swept[0])
    if target and not ctx.people.is_at(target, ctx.node, since):
        if swept is not None:   # looked all around here just now: not here
            ctx.log.append((now, f"{target} not seen in the look around "
                                 f"{ctx.graph.names[ctx.node]} {now - swept[1]:.0f} s ago"))
            return search_next(ctx, instruction, now)
        if ctx.config.look_headings > 0:
            return start_look(ctx, instruction_id, now)
        if ctx.config.verify_wait_s > 0:
            until = now + ctx.config.verify_wait_s
            ctx.mode, ctx.verifying = VERIFYING, (instruction_id, until)
            ctx.log.append((now, f"look for {target} at {ctx.graph.names[ctx.node]}"))
            return [Verify(instruction_id, target, until)]
        return search_next(ctx, instruction, now)
    return execute(ctx, instruction, function, now)


def stranger_here(ctx: Context, since: float) -> bool:
    """Perception saw someone at the robot's place at or after `since` [s] whom it cannot
    tell, and their whole shirt: the introduction node knows its strangers by their shirts, so
    a half-seen resident is not the stranger to greet (their answers would be refused)."""
    return ctx.people.unidentified_at(ctx.node, since, shirt=True) is not None


def meet_here(ctx: Context, instruction: Instruction, swept: tuple[float, float] | None,
              now: float) -> list[Command]:
    """Greet the stranger once perception saw someone here it cannot tell, whole shirt and
    all, within `stranger_fresh_s`; else look around for them, or give the meeting up when a
    look all around just now saw nobody such. Without frames from perception (it reports none
    to this robot) the robot cannot look for them: it greets on arrival."""
    if not ctx.people.perceiving() or stranger_here(ctx, now - ctx.config.stranger_fresh_s):
        return execute(ctx, instruction, function_for(ctx.functions, instruction), now)
    place = ctx.graph.names[ctx.node]
    if swept is not None and not stranger_here(ctx, swept[0]):
        return fail(ctx, instruction.id, now,
                    f"nobody unknown seen in a whole shirt in the look around {place}")
    if ctx.config.look_headings <= 0:
        return fail(ctx, instruction.id, now, f"nobody unknown seen in a whole shirt at {place}")
    return start_look(ctx, instruction.id, now)


def recent_sweep(ctx: Context, now: float) -> tuple[float, float] | None:
    """(start, end) [s] of a look all around the robot's place that ended at most
    `look_again_s` ago, else None."""
    swept = ctx.swept.get(ctx.node)
    if ctx.config.look_again_s <= 0 or swept is None or now - swept[1] > ctx.config.look_again_s:
        return None
    return swept


def stand_and_look(ctx: Context, now: float) -> list[Command]:
    """While standing to look for the target person: execute once they are here, else search
    on when the wait is over."""
    instruction_id, until = ctx.verifying_now()
    record = ctx.buffer.get(instruction_id)
    if ctx.people.is_at(record.instruction.target, ctx.node):
        ctx.mode, ctx.verifying = IDLE, None
        return execute(ctx, record.instruction, function_for(ctx.functions, record.instruction),
                       now)
    if now < until:
        return []
    ctx.mode, ctx.verifying = IDLE, None
    return search_next(ctx, record.instruction, now)


def start_look(ctx: Context, instruction_id: int, now: float) -> list[Command]:
    """Turn through `look_headings` headings on this node (evenly spaced after the one the
    robot arrived with), perception watching meanwhile."""
    count = max(1, ctx.config.look_headings)
    yaw = float(ctx.graph.pose(ctx.node)[2])
    headings = [yaw + 2.0 * math.pi * k / (count + 1) for k in range(1, count + 1)]
    ctx.mode, ctx.looking = LOOKING, [instruction_id, headings[1:], now, None, None, None]
    ctx.faced = []
    target = ctx.buffer.get(instruction_id).instruction.target if instruction_id else ""
    what = f"for {target or 'the stranger'}" if instruction_id else "(patrol)"
    ctx.log.append((now, f"look around {ctx.graph.names[ctx.node]} {what}"))
    return [Navigate(ctx.node, instruction_id, yaw=headings[0])]


def look_step(ctx: Context, now: float) -> list[Command]:
    """A heading of the look was reached: dwell on it while perception catches up (the
    camera sees little while turning), then turn to the next one or end the look."""
    looking = ctx.looking_now()
    if ctx.config.look_dwell_s > 0 and looking[3] is None:
        end = now + ctx.config.look_dwell_s
        looking[3], looking[4] = end, now
        return [Wait(end)]
    if looking[5] in (FACING, TOLD) and ctx.config.ask_wait_s > 0:
        question = ask_who(ctx, now)
        if question:
            return question
    looking[3] = looking[4] = None
    if looking[5] == CALLING:
        looking[5] = CALLED
        return end_look(ctx, now)
    if looking[5] in (ASKING, TOLD) and len(ctx.faced) < MAX_FACED:
        looking[5] = None   # not them: someone else here may be, faced before turning on
        someone_else = face_someone(ctx, now)
        if someone_else:
            return someone_else
    elif looking[5] in (FACING, ASKING, TOLD):
        looking[5] = FACED
    instruction_id, headings = looking[:2]
    if headings:
        looking[1] = headings[1:]
        return [Navigate(ctx.node, instruction_id, yaw=headings[0])]
    return end_look(ctx, now)


def ask_who(ctx: Context, now: float) -> list[Command]:
    """The person faced is still someone perception cannot tell (a shirt half hidden, a light
    that shifts its colours, or hidden from the camera while faced): ask them whether they
    are the person looked for, and wait `ask_wait_s` for a yes to reach the belief
    (look_found then serves them); after a no, or when nobody answers, the look goes on. A
    meeting's stranger is asked nothing: the greeting asks their name."""
    looking = ctx.looking_now()
    instruction_id = looking[0]
    target = ctx.buffer.get(instruction_id).instruction.target
    if not target:
        return []
    return put_question(ctx, target, ASKING, now)


def put_question(ctx: Context, target: str, phase: str, now: float) -> list[Command]:
    """Ask about `target` at the robot's place (`phase` ASKING: the person faced, CALLING: the
    place) and hold the look `ask_wait_s` for a yes."""
    looking = ctx.looking_now()
    end = now + ctx.config.ask_wait_s
    looking[3], looking[4], looking[5] = end, now, phase
    place = ctx.graph.names[ctx.node]
    ctx.log.append((now, f"call {target} at {place}" if phase == CALLING else
                    f"ask whether the person at {place} is {target}"))
    return [Ask(looking[0], target, place, call=phase == CALLING), Wait(end)]


def not_answered(ctx: Context, name: str, place: str, now: float) -> bool:
    """The person asked at `place` whether they are `name` said no, or nobody answered: the
    look stops waiting for a yes and turns on at the next tick. False when the robot is not
    waiting for that answer."""
    looking = ctx.looking
    if looking is None or looking[5] not in (ASKING, CALLING) or \
            ctx.graph.names[ctx.node] != place or \
            ctx.buffer.get(looking[0]).instruction.target != name:
        return False
    looking[3] = min(looking[3], now)
    ctx.log.append((now, f"the person at {place} is not {name}"))
    return True


def call_out(ctx: Context, now: float) -> list[Command]:
    """The look saw no sign of the person where the robot believed them or their schedule puts
    them: call them by name ("Bob, are you here?", the Ask's `call`) and wait `ask_wait_s` for
    a yes (look_found then serves them). A person hidden from the camera, seated behind a table
    or lying in bed, answers; the robot asks once per look, and only where they are expected,
    since a call at every place searched would cost each miss the wait."""
    looking = ctx.looking_now()
    instruction_id = looking[0]
    if ctx.config.ask_wait_s <= 0 or not instruction_id or looking[5] in (CALLING, CALLED):
        return []
    target = ctx.buffer.get(instruction_id).instruction.target
    if not target or ctx.node not in (ctx.people.now.get(target),
                                      ctx.people.predicted.get(target)):
        return []
    return put_question(ctx, target, CALLING, now)


def end_look(ctx: Context, now: float) -> list[Command]:
    """The look is over without finding an instruction's person: call them where they are
    expected (call_out), else search on (or decide)."""
    calling = call_out(ctx, now)
    if calling:
        return calling
    looking = ctx.looking_now()
    instruction_id, since = looking[0], looking[2]
    ctx.looked_s[ctx.node] = now
    ctx.swept[ctx.node] = (since, now)
    ctx.mode, ctx.looking = IDLE, None
    if not instruction_id:
        ctx.patrol_goal = None
        return ctx.decide(now)
    record = ctx.buffer.get(instruction_id)
    if not record.is_open:
        return ctx.decide(now)
    if is_meeting(ctx.functions, record.instruction):
        place = ctx.graph.names[ctx.node]
        return fail(ctx, instruction_id, now, f"nobody unknown seen in a whole shirt in the "
                                              f"look around {place}") + ctx.decide(now)
    return search_next(ctx, record.instruction, now) + ctx.decide(now)


def dwell_over(ctx: Context, now: float) -> bool:
    """The dwell on the heading is over: its time has passed and perception analysed
    `look_frames` frames taken since the heading was reached (when perception reports its
    frames), or the heading was held `look_frames_wait_s`. On a loaded machine perception
    analyses fewer frames per second of simulated time; counting frames keeps the look as
    thorough as on an idle one."""
    looking = ctx.looking_now()
    end, reached = looking[3], looking[4]
    if end is None or now < end:
        return False
    if looking[5] == TOLD:
        return True
    if looking[5] == FACING:
        return now - reached >= ctx.config.look_frames_wait_s
    if looking[5] in (ASKING, CALLING):
        return True
    if ctx.config.look_frames <= 0 or not ctx.people.perceiving():
        return True
    return (ctx.people.frames_since(reached) >= ctx.config.look_frames
            or now - reached >= ctx.config.look_frames_wait_s)


def face_someone(ctx: Context, now: float) -> list[Command]:
    """While looking for an instruction's person: turn to face a person perception saw at this
    place but could not tell (from behind, half hidden by a chair), and watch them for
    `look_frames_wait_s`: they may be the person looked for, and a turn in place that sees
    them at the edge of the image never shows their shirt. Once per look, or, when the robot
    asks (ask_who) and hears a no, once per person up to MAX_FACED."""
    looking = ctx.looking_now()
    instruction_id, _, since = looking[:3]
    if not instruction_id or looking[5] is not None or ctx.config.look_frames <= 0:
        return []
    someone = ctx.people.unidentified_at(ctx.node, since, away_from=ctx.faced)
    if someone is None:
        return []
    ctx.faced.append(someone)
    x, y, _ = ctx.graph.pose(ctx.node)
    yaw = math.atan2(someone[1] - y, someone[0] - x)
    looking[3:] = [None, None, FACING]
    ctx.log.append((now, f"face someone at {ctx.graph.names[ctx.node]} perception cannot tell"))
    return [Navigate(ctx.node, instruction_id, yaw=yaw)]


def told_faced(ctx: Context, now: float) -> None:
    """While facing someone perception could not tell: once it tells them, where they stand,
    as someone other than the person looked for (their shirt seen at last), the watch is over
    and they are asked at once (look_found serves the person looked for). They are asked
    rather than taken for that someone: a resident in new clothes may match another's shirt
    (Carol in pyjamas told as Alice, who was working in the office), and the seed resolves
    similar shirts by asking, never by guessing."""
    looking = ctx.looking_now()
    if looking[5] != FACING or looking[4] is None or not ctx.faced:
        return
    target = ctx.buffer.get(looking[0]).instruction.target
    x, y = ctx.faced[-1]
    if ctx.people.told_near(ctx.node, x, y, looking[4]) - {target}:
        looking[5] = TOLD
        ctx.log.append((now, f"perception tells the person faced at "
                             f"{ctx.graph.names[ctx.node]} as someone other than "
                             f"{target or 'the stranger'}"))


def look_found(ctx: Context, now: float) -> list[Command]:
    """While looking for an instruction's person: serve them once perception sees them."""
    looking = ctx.looking_now()
    instruction_id, _, since = looking[:3]
    if not instruction_id:
        return []
    instruction = ctx.buffer.get(instruction_id).instruction
    found = stranger_here(ctx, since) if is_meeting(ctx.functions, instruction) else \
        ctx.people.is_at(instruction.target, ctx.node, since)
    if not found:
        return []
    ctx.mode, ctx.looking = IDLE, None
    ctx.looked_s[ctx.node] = now
    return [StopMotion()] + execute(ctx, instruction, function_for(ctx.functions, instruction),
                                    now)


class StandingToLook(Leaf):
    """While standing to look for a person: serve them, or search on when the wait is over."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("stand and look", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.mode != VERIFYING:
            return Status.FAILURE
        ctx.out += stand_and_look(ctx, ctx.now)
        return still_busy(ctx, VERIFYING)


class LookingAround(Leaf):
    """While looking around: serve the person once seen; after a heading's dwell, turn on."""

    def __init__(self, ctx: Context) -> None:
        super().__init__("look around", ctx)

    def step(self, ctx: Context) -> Status:
        if ctx.mode != LOOKING:
            return Status.FAILURE
        ctx.out += look_found(ctx, ctx.now)
        if ctx.mode == LOOKING:
            ctx.out += face_someone(ctx, ctx.now)
            told_faced(ctx, ctx.now)
        if ctx.mode == LOOKING and dwell_over(ctx, ctx.now):
            ctx.out += look_step(ctx, ctx.now)
        return still_busy(ctx, LOOKING)
