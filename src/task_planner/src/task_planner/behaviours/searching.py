"""Searching for a person who is not where the robot believed them (ROS-free): where to serve an
instruction (its destination, the place being searched, or where its person was last seen), and
the next place to search after a miss; with none left, once more the places where someone
perception could not tell was seen, then "<name> not found".
"""
from dataclasses import replace

from task_planner.behaviours.context import Context
from task_planner.behaviours.serving import end_search, fail
from task_planner.executor_commands import Command
from task_planner.instruction import DURATION_MAX_S, Instruction
from task_planner.people_belief import miss_chance, search_order
from task_planner.robot_functions import is_meeting

MISS_STEP_S = 5   # [s] the expected cost of a miss is planned in steps of this: the planner is
#                   reset only when an instruction's copy changes, not as a sighting ages


def where(ctx: Context, instruction: Instruction) -> int:
    """Where to serve an instruction. Following the belief: where its person was last seen,
    else the next place of their search (planned once, from where the robot is, so the goal
    does not change as the robot moves; but the place their schedule puts them in now goes
    first, as the schedule turns to a new entry). Otherwise: the place being searched, else
    its destination."""
    target, key = instruction.target, instruction.id
    if ctx.config.follow_belief and target:
        seen = ctx.people.now.get(target)
        if seen is not None:
            return seen
        if key not in ctx.search and ctx.config.search_all_places:
            ctx.search[key] = search_order(target, ctx.people, ctx.looked_s,
                                           range(ctx.graph.size), ctx.searched.get(key, ()),
                                           ctx.graph.shortest[ctx.node], ctx.swept,
                                           ctx.config.pass_through)
        scheduled, queue = ctx.people.predicted.get(target), ctx.search.get(key)
        if queue and scheduled in queue[1:]:
            ctx.search[key] = [scheduled, *(n for n in queue if n != scheduled)]
    queue = ctx.search.get(key)
    return queue[0] if queue else instruction.destination


def served_where(ctx: Context, instruction: Instruction, now: float) -> Instruction:
    """The instruction as the planner takes it at `now` [s]: with the destination it is
    served at, and the time it is expected to take there: for a function that usually ends
    early (a meeting's dialogue) `RobotFunction.expected_s`, not its time limit; for a
    person's, following the belief, plus the expected cost of finding them not there
    (beyond the seed: miss_chance x search_miss_s, in steps of MISS_STEP_S). Copied only when
    either differs: a flood of instructions is decoded at every decision."""
    place = where(ctx, instruction)
    function = ctx.functions.get(instruction.function)
    duration = instruction.duration if function is None or function.expected_s is None else \
        min(instruction.duration, int(function.expected_s))
    if ctx.config.follow_belief and ctx.config.search_miss_s > 0 and instruction.target \
            and not is_meeting(ctx.functions, instruction):
        chance = miss_chance(ctx.people, instruction.target, place, now, ctx.config.stay_s)
        miss_s = MISS_STEP_S * round(chance * ctx.config.search_miss_s / MISS_STEP_S)
        duration = min(DURATION_MAX_S, duration + miss_s)
    return instruction if place == instruction.destination and \
        duration == instruction.duration else \
        replace(instruction, destination=place, duration=duration)


def search_next(ctx: Context, instruction: Instruction, now: float) -> list[Command]:
    """Person not here: go on to their next last known place, or fail having searched all."""
    searched = ctx.searched.setdefault(instruction.id, [])
    if not searched:
        ctx.search_start[instruction.id] = now
    searched.append(ctx.node)
    ctx.people.missed(instruction.target, ctx.node)
    share_miss(ctx, instruction, now)
    if ctx.config.search_all_places:
        queue = search_order(instruction.target, ctx.people, ctx.looked_s,
                             range(ctx.graph.size), searched, ctx.graph.shortest[ctx.node],
                             ctx.swept, ctx.config.pass_through)
    else:
        left = ctx.search.get(instruction.id)
        if left is None:  # first miss, at the instruction's own destination
            left = ctx.people.last_known_places(instruction.target)
        queue = [p for p in left if p not in searched]
    if queue:
        ctx.search[instruction.id] = queue
        ctx.log.append((now, f"{instruction.target} not at {ctx.graph.names[ctx.node]}; "
                             f"search {ctx.graph.names[queue[0]]}"))
        return []
    again = look_again_at(ctx, instruction, now)
    if again:
        ctx.search[instruction.id] = again
        ctx.log.append((now, f"{instruction.target} not seen anywhere; look again at "
                             f"{ctx.graph.names[again[0]]}, where someone perception could not "
                             f"tell was"))
        return []
    looked = ", ".join(ctx.graph.names[n] for n in searched)
    end_search(ctx, instruction, now, found=False)
    return fail(ctx, instruction.id, now,
                f"{instruction.target} not found (searched {looked})")


def share_miss(ctx: Context, instruction: Instruction, now: float) -> None:
    """A look here missed the person for each of their searches under way, not only this
    instruction's: their other instructions do not come back to look at this place again."""
    for key, queue in ctx.search.items():
        if key == instruction.id or ctx.node not in queue or not ctx.buffer.holds(key):
            continue
        if ctx.buffer.get(key).instruction.target != instruction.target:
            continue
        ctx.search[key] = [p for p in queue if p != ctx.node]
        ctx.searched.setdefault(key, []).append(ctx.node)
        ctx.search_start.setdefault(key, now)


def look_again_at(ctx: Context, instruction: Instruction, now: float) -> list[int]:
    """Every place searched, the person not seen: the places where, since the search began
    (from the start of the look that missed them there), perception saw someone it could not
    tell (sitting half hidden, seen from behind), where the person was seen before first, then
    the nearest, each looked at once more for this instruction (the place just looked at is
    not): that someone may be the person, and a second look often shows the shirt the first
    missed. Once chosen, the second looks go on through that list, and the search ends with
    it."""
    key = instruction.id
    if key in ctx.rechecked:   # second looks under way: the rest of them
        return [n for n in ctx.search.get(key, ()) if n != ctx.node and n in ctx.rechecked[key]]
    start = ctx.search_start.get(key, now)   # the first miss, at the end of its look
    known = ctx.people.last_known_places(instruction.target)
    places = [n for n in dict.fromkeys(ctx.searched.get(key, ()))
              if n != ctx.node and ctx.people.unidentified_at(
                  n, min(start, ctx.swept.get(n, (start,))[0])) is not None]
    places.sort(key=lambda n: (n not in known, float(ctx.graph.shortest[ctx.node][n])))
    ctx.rechecked[key] = set(places)
    return places
