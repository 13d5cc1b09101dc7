"""task_planner.behaviours.patrolling: an idle robot looks at the stalest, likeliest place."""
import math

from behaviour_factories import A, B, C, D, make_context
from task_planner.behaviours.patrolling import patrol
from task_planner.executor_commands import LOOKING, MOVING, Navigate
from task_planner.people_belief import PeopleAtPlaces


def test_the_patrol_drives_toward_the_place_someone_is_expected(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.predicted["Carol"] = C
    ctx = make_context(posed_line_graph, tmp_path, people=people, patrol_interval_s=30.0)
    ctx.looked_s.update({A: 0.0, B: 0.0, C: 0.0, D: 0.0})
    assert patrol(ctx, 100.0) == [Navigate(B, 0)]           # the first edge on the way to C
    assert (ctx.mode, ctx.goal, ctx.goal_for, ctx.patrol_goal) == (MOVING, B, 0, C)
    assert ctx.log[-1] == (100.0, "patrol to C")


def test_the_patrol_looks_around_where_it_stands_and_rests_when_all_is_fresh(
        posed_line_graph, tmp_path):
    ctx = make_context(posed_line_graph, tmp_path, node=B, patrol_interval_s=30.0,
                       look_headings=1)
    ctx.looked_s.update({A: 90.0, C: 90.0, D: 90.0})        # B never looked at: here
    assert patrol(ctx, 100.0) == [Navigate(B, 0, yaw=math.pi)]
    assert ctx.mode == LOOKING
    (tmp_path / "fresh").mkdir()
    fresh = make_context(posed_line_graph, tmp_path / "fresh", patrol_interval_s=30.0)
    fresh.looked_s.update({n: 90.0 for n in range(4)})
    assert patrol(fresh, 100.0) == [] and fresh.mode == "idle"
