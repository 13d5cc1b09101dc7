"""task_planner.behaviours.serving: start, finish and fail a robot function."""
import pytest
from behaviour_factories import A, B, make_context, journal
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.behaviours.serving import Executing, execute, fail, finish, give_up_waiting
from task_planner.executor_commands import EXECUTING, IDLE, Execute, Say
from task_planner.task_buffer import ACTIVE, DONE, FAILED, BufferConfig, TaskBuffer


def test_execute_starts_the_function_and_says_its_line(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, node=B)
    record, = journal(ctx, make_instruction(1, B, duration=20, function=3, target="Bob"))
    commands = execute(ctx, record.instruction, ctx.functions[3], 5.0)
    assert commands == [Execute(1, "check_status", 20.0),
                        Say("Bob, how are you feeling right now?")]
    assert ctx.mode == EXECUTING and ctx.executing == (1, 25.0)
    assert ctx.buffer.get(1).state == ACTIVE


def test_finish_writes_back_the_decayed_reward(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, node=A)
    record, = journal(ctx, make_instruction(1, A, gamma=3.0, beta=0.9, duration=10, function=1))
    execute(ctx, record.instruction, ctx.functions[1], 0.0)
    finish(ctx, 10.0)
    done = ctx.buffer.get(1)
    assert done.state == DONE and done.reward_earned == pytest.approx(3.0 * 0.9 ** 10)
    assert ctx.mode == IDLE and ctx.log[-1] == (10.0, "done 1: reward 1.046")


def test_the_person_served_is_believed_where_they_were_served(line_graph, tmp_path):
    """Bob was seen at B when his chat began at 0 s, not since (seated, half hidden): at its
    end he is believed at B, seen then, so his next request at B is served at once."""
    ctx = make_context(line_graph, tmp_path, node=B)
    ctx.people.seen("Bob", B, 0.0)
    record, = journal(ctx, make_instruction(1, B, duration=60, function=1, target="Bob"))
    execute(ctx, record.instruction, ctx.functions[1], 0.0)
    finish(ctx, 60.0)
    assert ctx.people.is_at("Bob", B, since=60.0)


def test_the_executing_leaf_runs_until_the_time_is_up(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    leaf = Executing(ctx)
    ctx.now = 0.0
    leaf.tick_once()
    assert leaf.status == Status.FAILURE        # not executing: the next leaf decides
    record, = journal(ctx, make_instruction(1, A, duration=10, function=1))
    execute(ctx, record.instruction, ctx.functions[1], 0.0)
    ctx.now = 9.9
    leaf.tick_once()
    assert leaf.status == Status.RUNNING
    ctx.now = 10.0
    leaf.tick_once()
    assert leaf.status == Status.FAILURE and ctx.buffer.get(1).state == DONE


def test_fail_journals_the_reason_and_apologises(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    journal(ctx, make_instruction(1, B, function=1))
    ctx.search[1], ctx.searched[1] = [2], [B]   # a search on to C
    assert fail(ctx, 1, 3.0, "no way") == [Say("Sorry, I could not complete request 1.")]
    record = ctx.buffer.get(1)
    assert (record.state, record.reason) == (FAILED, "no way")
    assert 1 not in ctx.search and 1 not in ctx.searched


def test_a_successor_fails_when_its_predecessor_never_arrives(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    ctx.buffer = TaskBuffer(tmp_path / "wait.sqlite",
                            BufferConfig(node_count=4, predecessor_wait_s=60.0))
    journal(ctx, make_instruction(2, B, function=1, previous_id=1))
    assert give_up_waiting(ctx, 59.0) == []
    assert give_up_waiting(ctx, 60.0) == [Say("Sorry, I could not complete request 2.")]
    assert ctx.buffer.get(2).state == FAILED
