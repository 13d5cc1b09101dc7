"""task_planner.behaviours.accounting: what the robot does now, and time per activity."""
import pytest
from behaviour_factories import A, B, C, make_context, journal
from planner_factories import make_instruction

from task_planner.behaviours.accounting import (DIALOGUE, FUNCTION, IDLE, LOOK_AROUND, PATROL,
                                                SEARCHING, TRAVEL, WAITING, activity,
                                                time_shares)
from task_planner.behaviours.looking import look_step, serve_here
from task_planner.behaviours.recovery import recover
from task_planner.behaviours.serving import execute
from task_planner.executor_commands import MOVING
from task_planner.people_belief import PeopleAtPlaces


def test_travel_then_look_around_then_searching(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Bob", C, stamp=0.0)
    people.seen("Bob", B, stamp=1.0)
    ctx = make_context(posed_line_graph, tmp_path, node=A, people=people, look_headings=2,
                       fresh_s=1.0)
    assert activity(ctx) == IDLE
    journal(ctx, make_instruction(1, B, function=3, target="Bob"))
    ctx.mode, ctx.goal, ctx.goal_for = MOVING, B, 1
    assert activity(ctx) == TRAVEL
    ctx.node, ctx.mode = B, "idle"
    serve_here(ctx, 1, 10.0)                         # not seen since 1 s: look around B
    assert activity(ctx) == LOOK_AROUND
    ctx.looking[1] = []
    look_step(ctx, 12.0)                             # the look ends: search C next
    ctx.mode, ctx.goal, ctx.goal_for = MOVING, C, 1
    assert ctx.searched[1] == [B] and activity(ctx) == SEARCHING


def test_waiting_patrol_dialogue_and_functions(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, pass_wait_s=4.0)
    journal(ctx, make_instruction(1, C, function=1),
            make_instruction(2, A, duration=60, function=9),       # introduce
            make_instruction(3, A, duration=20, function=3))
    ctx.mode, ctx.goal, ctx.goal_for, ctx.attempts = MOVING, B, 1, 1
    recover(ctx, 1.0, "blocked")                     # asks to pass and waits
    assert activity(ctx) == WAITING
    ctx.retry_at, ctx.goal_for = None, 0
    assert activity(ctx) == PATROL
    ctx.mode = "idle"
    execute(ctx, ctx.buffer.get(2).instruction, ctx.functions[9], 2.0)
    assert activity(ctx) == DIALOGUE
    ctx.buffer.finish(2, 62.0)
    ctx.mode = "idle"
    execute(ctx, ctx.buffer.get(3).instruction, ctx.functions[3], 3.0)
    assert activity(ctx) == FUNCTION


def test_time_shares_sum_each_activity_until_the_next_change():
    changes = [[-5.0, IDLE], [2.0, TRAVEL], [10.0, FUNCTION], [30.0, TRAVEL], [35.0, IDLE]]
    shares = time_shares(changes, 0.0, 40.0)
    assert shares == pytest.approx({IDLE: 2.0 + 5.0, TRAVEL: 8.0 + 5.0, FUNCTION: 20.0})
    assert sum(shares.values()) == pytest.approx(40.0)
    assert time_shares([], 0.0, 10.0) == {}
