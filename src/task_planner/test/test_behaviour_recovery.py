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
    stays, at most corridor_wait_s (10 s) from its first wait, then gives the instruction back
    to the fleet."""
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
    assert recover(ctx, 11.0, "stuck") == []              # 10 s: given back, nothing else
    assert ctx.buffer.get(1).state == PENDING and ctx.left_to_others(11.0) == {1}
    assert ctx.log[-1] == (11.0, "give 1 back to the fleet (1 of 2): navigation to B aborted "
                                 "1 times: stuck")


def test_in_a_fleet_an_unreachable_place_goes_back_to_the_pool_then_fails(line_graph,
                                                                          tmp_path):
    """No robot at the goal: the instruction goes back to the pool (another robot may reach
    its place), left to the others for corridor_wait_s, at most max_handbacks (2) times; the
    third time it fails. The robot's own instructions (kept local) fail at once."""
    pool = tmp_path / "pool.sqlite"
    FleetLink(FleetPool(pool), "b").report(C, 0.0, 0.0)
    ctx = make_context(line_graph, tmp_path, max_goal_attempts=1, corridor_wait_s=30.0)
    ctx.fleet = FleetLink(FleetPool(pool), "a")
    journal(ctx, make_instruction(1, C, function=1))
    for k, now in enumerate((1.0, 40.0)):
        moving_for(ctx, 1, B)
        assert recover(ctx, now, "stuck") == []
        assert ctx.buffer.get(1).state == PENDING and ctx.given_back[1] == (now, k + 1)
        assert ctx.left_to_others(now + 29.0) == {1} and ctx.left_to_others(now + 30.0) == set()
    moving_for(ctx, 1, B)
    recover(ctx, 80.0, "stuck")
    assert ctx.buffer.get(1).state == FAILED
    assert ctx.buffer.get(1).reason == "navigation to B aborted 1 times: stuck"
    journal(ctx, make_instruction(2, C, function=1))
    ctx.fleet.keep_local(2)
    moving_for(ctx, 2, B)
    recover(ctx, 81.0, "stuck")
    assert ctx.buffer.get(2).state == FAILED and 2 not in ctx.given_back


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
