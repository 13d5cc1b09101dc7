"""task_planner.behaviours.patrolling: an idle robot looks at the stalest, likeliest place."""
import math

from behaviour_factories import A, B, C, D, make_context
from task_planner.behaviours.patrolling import clear_corridor, patrol
from task_planner.executor_commands import LOOKING, MOVING, Navigate, Wait
from task_planner.fleet_link import FleetLink
from task_planner.fleet_pool import FleetPool
from task_planner.people_belief import PeopleAtPlaces


def test_the_patrol_drives_toward_the_place_someone_is_expected(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.predicted["Carol"] = C
    ctx = make_context(posed_line_graph, tmp_path, people=people, patrol_interval_s=30.0)
    ctx.looked_s.update({A: 0.0, B: 0.0, C: 0.0, D: 0.0})
    assert patrol(ctx, 100.0) == [Navigate(B, 0, through=0.0)]  # the first edge on the way to C
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


def test_in_a_fleet_an_idle_robot_leaves_a_corridor_and_never_patrols_one(posed_line_graph,
                                                                          tmp_path):
    """B and C are corridors. A fleet robot idle in C, with every place looked at lately, drives
    to the nearest place that is none (A and D are 3 m away: the lower node wins); its patrol
    picks A or D, never the corridors, even though nobody ever looked at them. Alone, a robot
    stays where it is."""
    ctx = make_context(posed_line_graph, tmp_path, node=C, corridors=(B, C), patrol=True,
                       patrol_interval_s=30.0)
    ctx.fleet = FleetLink(FleetPool(tmp_path / "pool.sqlite"), "a")
    ctx.looked_s.update({n: 90.0 for n in range(4)})
    assert patrol(ctx, 100.0) == []
    assert clear_corridor(ctx, 100.0) == [Navigate(B, 0, through=math.pi)]  # on the way to A
    assert ctx.patrol_goal == A and ctx.mode == MOVING
    assert ctx.log[-1] == (100.0, "clear the corridor C for A")
    (tmp_path / "stale").mkdir()
    stale = make_context(posed_line_graph, tmp_path / "stale", node=C, corridors=(B, C),
                         patrol=True, patrol_interval_s=30.0)
    stale.fleet = FleetLink(FleetPool(tmp_path / "stale" / "pool.sqlite"), "a")
    stale.looked_s.update({A: 0.0, D: 0.0})                        # B, C never looked at
    patrol(stale, 100.0)
    assert stale.patrol_goal in (A, D)
    (tmp_path / "alone").mkdir()
    alone = make_context(posed_line_graph, tmp_path / "alone", node=C, corridors=(B, C))
    assert clear_corridor(alone, 100.0) == [] and alone.mode == "idle"


def test_the_patrol_passes_over_places_people_only_pass_through(posed_line_graph, tmp_path):
    """B is a passage (`pass_through`): at the start of a day, nothing looked at and nobody
    expected anywhere, the robot on B does not look around there but heads for the nearest
    place people stay (A and C are equally near: the lower node); once Carol is expected on B,
    the patrol looks there."""
    ctx = make_context(posed_line_graph, tmp_path, node=B, pass_through=(B,),
                       patrol_interval_s=30.0)
    patrol(ctx, 0.0)
    assert ctx.patrol_goal == A and ctx.mode == MOVING
    (tmp_path / "expected").mkdir()
    people = PeopleAtPlaces()
    people.predicted["Carol"] = B
    expected = make_context(posed_line_graph, tmp_path / "expected", node=B, people=people,
                            pass_through=(B,), patrol_interval_s=30.0, look_headings=1)
    patrol(expected, 0.0)
    assert expected.mode == LOOKING


def test_a_patrol_waits_for_a_corridor_another_robot_holds(posed_line_graph, tmp_path):
    """An idle move takes the corridor lock as any move: two robots meeting head-on in the
    alley block each other."""
    pool = tmp_path / "pool.sqlite"
    FleetLink(FleetPool(pool), "b").enter({"B"}, 100.0)
    people = PeopleAtPlaces()
    people.predicted["Carol"] = C
    ctx = make_context(posed_line_graph, tmp_path, people=people, corridors=(B,),
                       patrol=True, patrol_interval_s=30.0, corridor_poll_s=1.0)
    ctx.fleet = FleetLink(FleetPool(pool), "a")
    ctx.looked_s.update({A: 0.0, B: 0.0, C: 0.0, D: 0.0})
    assert patrol(ctx, 100.0) == [Wait(101.0)]                 # through B to C: b is in B
    assert (ctx.mode, ctx.goal, ctx.patrol_goal) == (MOVING, B, C)
    assert ctx.log[-1] == (100.0, "wait: b is in B")
