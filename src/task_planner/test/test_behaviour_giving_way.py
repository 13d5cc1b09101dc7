"""task_planner.behaviours.giving_way: a person's request interrupts the robot's own."""
from behaviour_factories import A, make_context, journal
from planner_factories import make_instruction

from task_planner.behaviours.giving_way import yield_own
from task_planner.behaviours.serving import execute
from task_planner.executor_commands import IDLE, Say, StopMotion
from task_planner.instruction import ROBOT
from task_planner.task_buffer import PENDING


def own(ctx, function):
    record, = journal(ctx, make_instruction(1, A, duration=100, function=function, type=ROBOT,
                                            source="robot"))
    execute(ctx, record.instruction, ctx.functions[function], 0.0)


def test_the_robots_own_music_gives_way_and_waits(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, own_yields=True)
    own(ctx, 6)                                      # play_music
    assert yield_own(ctx, 5.0) == [StopMotion(), Say(ctx.config.yield_notice)]
    assert ctx.mode == IDLE and ctx.buffer.get(1).state == PENDING and ctx.deferred == {1}


def test_charging_is_never_interrupted_nor_anything_without_own_yields(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, own_yields=True)
    own(ctx, 8)                                      # charge: in own_kept
    assert yield_own(ctx, 5.0) == [] and ctx.mode == "executing"
    (tmp_path / "off").mkdir()
    off = make_context(line_graph, tmp_path / "off", own_yields=False)
    own(off, 6)
    assert yield_own(off, 5.0) == [] and off.mode == "executing"
