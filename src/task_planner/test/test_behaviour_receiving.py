"""task_planner.behaviours.receiving: journal new instructions, then react."""
from behaviour_factories import A, B, C, make_context
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.behaviours.context import RECEIVED, TICK
from task_planner.behaviours.receiving import TakingIn, new_id, take_in
from task_planner.executor_commands import MOVING, Navigate


def test_take_in_journals_and_decides_at_once(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    results, commands = take_in(ctx, [make_instruction(1, C, function=1)], 0.0)
    assert [r.instruction.id for r, _ in results] == [1]
    assert commands == [Navigate(B, 1)] and ctx.mode == MOVING
    assert ctx.log[0] == (0.0, "received 1")


def test_a_refused_instruction_is_logged_and_decides_nothing(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    take_in(ctx, [make_instruction(1, C, function=1)], 0.0)
    (record, error), = take_in(ctx, [make_instruction(1, A, function=1)], 1.0)[0]
    assert record is None
    assert error == "instruction 1: id already used by a different instruction (pending)"
    assert ctx.log[-1] == (1.0, f"refused: {error}")


def test_the_leaf_takes_in_only_on_a_received_event(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    leaf = TakingIn(ctx)
    ctx.event, ctx.now, ctx.inbox, ctx.out = TICK, 0.0, [make_instruction(1, C)], []
    leaf.tick_once()
    assert leaf.status == Status.FAILURE and ctx.buffer.records() == []
    ctx.event = RECEIVED
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS and ctx.out == [Navigate(B, 1)]


def test_new_ids_follow_the_journal(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    assert new_id(ctx) == 1
    take_in(ctx, [make_instruction(7, A)], 0.0)
    assert new_id(ctx) == 8
