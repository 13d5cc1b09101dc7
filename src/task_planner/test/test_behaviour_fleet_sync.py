"""task_planner.behaviours.fleet_sync: news from the other robots, closures, and the rejoin."""
from behaviour_factories import A, B, D, make_context, robots
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.behaviours.context import ARRIVED, TICK
from task_planner.behaviours.fleet_sync import FleetSync, fleet_news
from task_planner.behaviours.receiving import take_in
from task_planner.executor_commands import MOVING, StopMotion
from task_planner.task_buffer import DONE, PENDING


def test_news_from_another_robot_is_journalled_and_decided_on(line_graph, tmp_path):
    a, b = robots(line_graph, tmp_path)
    take_in(b, [make_instruction(1, B, duration=5, function=1)], 0.0)   # b claims and drives
    a_news = fleet_news(a, 0.5)
    assert a.buffer.get(1).state == PENDING and a_news == []             # b holds it
    assert (0.5, "received 1") in a.log


def test_what_another_robot_closed_is_closed_here_too(line_graph, tmp_path):
    a, b = robots(line_graph, tmp_path)
    take_in(a, [make_instruction(1, A, duration=2, function=1)], 0.0)   # a serves it here
    fleet_news(b, 0.1)
    a.buffer.finish(1, 2.0)
    a.fleet.close(1, 2.0, DONE)
    fleet_news(b, 2.5)
    record = b.buffer.get(1)
    assert record.state == DONE and record.reason == "done by a"


def test_a_rejoin_stops_a_robot_whose_instruction_another_robot_took(line_graph, tmp_path):
    a, b = robots(line_graph, tmp_path)
    take_in(a, [make_instruction(1, D, duration=2, function=1)], 0.0)
    assert a.mode == MOVING and a.goal_for == 1
    a.fleet.release()                       # a's claim lapses (as after a lost connection)
    fleet_news(b, 0.5)
    assert b.fleet.claim(1, 0.5, D)         # b takes it
    a.in_fleet = False                      # a rejoins at its next event: an arrival
    leaf = FleetSync(a)
    a.event, a.now, a.out = ARRIVED, 1.0, []
    leaf.tick_once()
    assert a.out == [StopMotion()] and leaf.status == Status.FAILURE   # the arrival is void
    assert (1.0, "lost 1 to another robot") in a.log and a.mode != MOVING


def test_a_robot_on_its_own_has_nothing_to_sync(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    leaf = FleetSync(ctx)
    ctx.event, ctx.now, ctx.out = TICK, 0.0, []
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS and ctx.out == [] and fleet_news(ctx, 0.0) == []
