"""task_planner.behaviours.dropping: a cancel stops what the robot serves and decides again."""
from behaviour_factories import A, B, D, make_context, journal
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.behaviours.context import CANCELLED, TICK
from task_planner.behaviours.dropping import Cancelling, cancel
from task_planner.behaviours.serving import execute
from task_planner.executor_commands import MOVING, Navigate
from task_planner.task_buffer import CANCELLED as CANCELLED_STATE


def test_cancelling_the_executing_instruction_stops_it_and_serves_the_next(line_graph,
                                                                           tmp_path):
    ctx = make_context(line_graph, tmp_path)
    first, _ = journal(ctx, make_instruction(1, A, duration=10, function=1),
                       make_instruction(2, D, duration=10, function=1))
    execute(ctx, first.instruction, ctx.functions[1], 0.0)
    assert cancel(ctx, ctx.buffer.get(1), 3.0) == [Navigate(B, 2)]
    assert ctx.buffer.get(1).state == CANCELLED_STATE and ctx.mode == MOVING
    assert (3.0, "closed 1: cancelled by request") in ctx.log


def test_the_cancel_leaf_acts_only_on_a_cancel(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    record, = journal(ctx, make_instruction(1, D, function=1))
    leaf = Cancelling(ctx)
    ctx.event, ctx.now, ctx.cancelled, ctx.out = TICK, 0.0, record, []
    leaf.tick_once()
    assert leaf.status == Status.FAILURE and ctx.buffer.get(1).is_open
    ctx.event = CANCELLED
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS and ctx.buffer.get(1).state == CANCELLED_STATE
