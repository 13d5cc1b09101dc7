"""task_planner.behaviours.driving: corridors before a move, arrivals, retries after a wait."""
from behaviour_factories import A, B, C, make_context, journal
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.behaviours.driving import Arriving, Driving, arrive, drive
from task_planner.behaviours.context import ARRIVED, TICK
from task_planner.executor_commands import EXECUTING, IDLE, MOVING, Navigate, Wait
from task_planner.fleet_link import FleetLink
from task_planner.fleet_pool import FleetPool


def test_an_arrival_moves_the_robot_on_and_decides(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    journal(ctx, make_instruction(1, C, duration=5, function=1))
    ctx.mode, ctx.goal, ctx.goal_for = MOVING, B, 1
    assert arrive(ctx, 2.0) == [Navigate(C, 1)]
    assert (ctx.node, ctx.goal, ctx.mode) == (B, C, MOVING)
    assert arrive(ctx, 6.0)[0].function == "chat" and ctx.mode == EXECUTING


def test_an_arrival_while_idle_is_an_error_not_a_silent_move(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    leaf = Arriving(ctx)
    ctx.event, ctx.now = ARRIVED, 1.0
    try:
        leaf.tick_once()
    except RuntimeError as error:
        assert str(error) == f"arrival reported while {IDLE}"
    else:
        raise AssertionError("an arrival while idle was taken")


def test_a_robot_waits_for_a_corridor_another_robot_holds(line_graph, tmp_path):
    pool = tmp_path / "pool.sqlite"
    other = FleetLink(FleetPool(pool), "b")
    other.enter({"B"}, 0.0)
    ctx = make_context(line_graph, tmp_path, corridors=(B,), corridor_wait_s=3.0,
                       corridor_poll_s=1.0)
    ctx.fleet = FleetLink(FleetPool(pool), "a")
    ctx.mode, ctx.goal, ctx.goal_for = MOVING, B, 1
    assert drive(ctx, 0.0) == [Wait(1.0)] and ctx.log[-1] == (0.0, "wait: b is in B")
    leaf = Driving(ctx)
    ctx.event, ctx.now, ctx.out = TICK, 1.0, []
    leaf.tick_once()
    assert leaf.status == Status.RUNNING and ctx.out == [Wait(2.0)]
    ctx.now, ctx.out = 3.0, []
    leaf.tick_once()                                 # waited corridor_wait_s: drive on
    assert ctx.out == [Navigate(B, 1)] and ctx.log[-1] == (3.0, "drive on after 3 s: b stays in B")


def test_the_drive_leaf_fails_unless_the_robot_drives(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, node=A)
    leaf = Driving(ctx)
    ctx.now = 0.0
    leaf.tick_once()
    assert leaf.status == Status.FAILURE
