"""task_planner.behaviours.recovery: ask to pass and retry an aborted goal, then fail; faults."""
from behaviour_factories import A, B, C, make_context, journal
from planner_factories import make_instruction

from task_planner.behaviours.recovery import fault, recover
from task_planner.behaviours.serving import execute
from task_planner.executor_commands import IDLE, MOVING, Navigate, Say, StopMotion, Wait
from task_planner.fleet_link import FleetLink
from task_planner.fleet_pool import FleetPool
from task_planner.task_buffer import FAILED, PENDING


def moving_for(ctx, instruction_id, goal):
    ctx.mode, ctx.goal, ctx.goal_for, ctx.attempts = MOVING, goal, instruction_id, 1


def test_an_abort_asks_to_pass_waits_and_then_fails_the_instruction(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, pass_wait_s=4.0, max_goal_attempts=2)
    journal(ctx, make_instruction(1, C, function=1))
    moving_for(ctx, 1, B)
    assert recover(ctx, 1.0, "blocked") == [Say("Excuse me, may I pass?"), Wait(5.0)]
    assert ctx.retry_at == 5.0 and ctx.attempts == 2
    assert recover(ctx, 7.0, "blocked") == []         # failed; nothing else to serve
    record = ctx.buffer.get(1)
    assert record.state == FAILED
    assert record.reason == "navigation to B aborted 2 times: blocked"
    assert ctx.mode == IDLE


def test_in_a_fleet_the_robot_waits_for_another_standing_at_the_goal(line_graph, tmp_path):
    """Retries spent, robot b reported at B (the goal): robot a waits and retries while b
    stays, at most corridor_wait_s (10 s) from its first wait, then fails the instruction."""
    pool = tmp_path / "pool.sqlite"
    other = FleetLink(FleetPool(pool), "b")
    other.report(B, 0.0, 0.0)
    ctx = make_context(line_graph, tmp_path, pass_wait_s=4.0, max_goal_attempts=1,
                       corridor_wait_s=10.0)
    ctx.fleet = FleetLink(FleetPool(pool), "a")
    journal(ctx, make_instruction(1, C, function=1))
    moving_for(ctx, 1, B)
    assert recover(ctx, 1.0, "stuck") == [Wait(5.0)]
    assert ctx.log[-1] == (1.0, "wait: b is at B; retry then") and ctx.mode == MOVING
    other.report(B, 0.0, 7.5)                             # b stays, within its lease
    assert recover(ctx, 8.0, "stuck") == [Wait(12.0)]     # 7 s into the wait
    other.report(B, 0.0, 10.5)
    assert recover(ctx, 11.0, "stuck") == []              # 10 s: failed
    assert ctx.buffer.get(1).state == FAILED


def test_in_a_fleet_a_robot_elsewhere_is_not_waited_for(line_graph, tmp_path):
    pool = tmp_path / "pool.sqlite"
    FleetLink(FleetPool(pool), "b").report(C, 0.0, 0.0)
    ctx = make_context(line_graph, tmp_path, max_goal_attempts=1)
    ctx.fleet = FleetLink(FleetPool(pool), "a")
    journal(ctx, make_instruction(1, C, function=1))
    moving_for(ctx, 1, B)
    assert recover(ctx, 1.0, "stuck") == [] and ctx.buffer.get(1).state == FAILED


def test_without_pass_wait_the_goal_is_sent_again_at_once(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, max_goal_attempts=3)
    journal(ctx, make_instruction(1, C, function=1))
    moving_for(ctx, 1, B)
    assert recover(ctx, 1.0, "x") == [Navigate(B, 1)]
    assert ctx.log[-1] == (1.0, "retry 2 to B")


def test_a_fault_fails_what_the_robot_served_and_stops(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    record, = journal(ctx, make_instruction(1, A, duration=10, function=1))
    execute(ctx, record.instruction, ctx.functions[1], 0.0)
    commands = fault(ctx, 2.0, "KeyError: 'x'")
    assert commands == [StopMotion(), Say("Sorry, I could not complete request 1.")]
    assert ctx.buffer.get(1).reason == "fault while serving it: KeyError: 'x'"
    assert ctx.mode == IDLE and ctx.executing is None


def test_a_fault_that_only_stops_leaves_the_instruction_to_another_robot(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    ctx.in_fleet = True
    record, = journal(ctx, make_instruction(1, A, duration=10, function=1))
    execute(ctx, record.instruction, ctx.functions[1], 0.0)
    assert fault(ctx, 2.0, "another robot's now", fail_it=False) == [StopMotion()]
    assert ctx.buffer.get(1).state == PENDING and ctx.log[-1] == (2.0,
                                                                 "stop: another robot's now")
    assert ctx.in_fleet is True      # not asked to rejoin: it stays in the fleet


def test_a_lost_pool_stops_leaves_the_instruction_open_and_rejoins_next(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    ctx.in_fleet = True
    record, = journal(ctx, make_instruction(1, A, duration=10, function=1))
    execute(ctx, record.instruction, ctx.functions[1], 0.0)
    assert fault(ctx, 2.0, "PoolUnavailable: ...", fail_it=False, rejoin=True) == [StopMotion()]
    assert ctx.buffer.get(1).state == PENDING and ctx.mode == IDLE
    assert ctx.in_fleet is False     # the next event rejoins the fleet first
