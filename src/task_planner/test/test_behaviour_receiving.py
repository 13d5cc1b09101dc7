"""task_planner.behaviours.receiving: journal new instructions, then react."""
from behaviour_factories import A, B, C, make_context
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.behaviours.context import RECEIVED, TICK
from task_planner.behaviours.receiving import TakingIn, new_id, take_in
from task_planner.fleet_link import FleetLink
from task_planner.fleet_pool import FleetPool
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


def test_beyond_the_cap_new_instructions_are_refused_naming_it(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, max_open=2)
    results, _ = take_in(ctx, [make_instruction(i, C, function=1) for i in (1, 2, 3)], 0.0,
                         capped=True)
    assert [(r.instruction.id if r else None, e) for r, e in results] == [
        (1, ""), (2, ""), (None, "instruction 3: the task buffer is full: 2 open instructions "
                                 "(at most 2)")]
    (record, error), = take_in(ctx, [make_instruction(4, C, function=1)], 1.0, capped=True)[0]
    assert record is None
    assert error == "instruction 4: the task buffer is full: 2 open instructions (at most 2)"
    assert ctx.log[-1] == (1.0, f"refused: {error}")
    again = make_instruction(1, C, function=1)   # a re-submission is no new instruction
    assert take_in(ctx, [again], 2.0, capped=True)[0][0][0].instruction == again
    ctx.buffer.cancel(2, 3.0)                     # room again
    assert take_in(ctx, [make_instruction(5, C, function=1)], 3.0, capped=True)[0][0][0]


def test_the_robots_own_instructions_are_not_capped(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, max_open=1)
    take_in(ctx, [make_instruction(1, C, function=1)], 0.0, capped=True)
    (record, error), = take_in(ctx, [make_instruction(2, C, function=1)], 0.0)[0]
    assert record is not None and error == ""


def test_the_cap_holds_in_a_fleet_and_the_refused_are_not_shared(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, max_open=1)
    ctx.fleet = FleetLink(FleetPool(tmp_path / "pool.sqlite"), "robot1")
    results, _ = take_in(ctx, [make_instruction(1, C, function=1),
                               make_instruction(2, C, function=1)], 0.0, capped=True)
    assert [e for _, e in results] == [
        "", "instruction 2: the task buffer is full: 1 open instruction (at most 1)"]
    other = FleetLink(FleetPool(tmp_path / "pool.sqlite"), "robot2")
    assert [i.id for i in other.news()] == [1]


def test_no_cap_takes_everything(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    results, _ = take_in(ctx, [make_instruction(i, C, function=1) for i in range(1, 30)], 0.0,
                         capped=True)
    assert all(record is not None for record, _ in results)
