"""task_planner.behaviours.fleet_allocation: two robots deciding with the fleet's auction; claims
move cleanly, nothing is held twice, and a robot executing keeps its instruction."""
import pytest
from behaviour_factories import A, B, C, D, robots
from planner_factories import make_instruction

from task_planner.behaviours.deciding import decide, fetch_and_decode, redecide
from task_planner.behaviours.fleet_allocation import fleet_allocator, free_point
from task_planner.behaviours.fleet_sync import fleet_news
from task_planner.behaviours.receiving import take_in
from task_planner.behaviours.serving import finish
from task_planner.executor_commands import EXECUTING, IDLE, MOVING
from task_planner.executor_sim import NavigationModel, run_executor_fleet
from task_planner.fleet_pool import CLAIMED, OPEN
from test_executor_fleet import fleet, served


def holders(ctx):
    """{instruction id: (pool state, holder)} of the pool."""
    return {e.id: (e.state, e.robot) for e in ctx.fleet.pool.entries()}


def test_the_auction_leaves_an_instruction_to_the_robot_that_serves_it_sooner(
        line_graph, tmp_path):
    a, b = robots(line_graph, tmp_path)
    fleet_news(b, 0.0)                                   # b reports: free on D now
    take_in(a, [make_instruction(1, D, duration=4, function=1)], 0.0)
    assert a.mode == IDLE and holders(a) == {1: (OPEN, "")}    # a leaves it to b
    fleet_news(b, 0.1)                                   # b takes it in and claims it
    assert b.mode == EXECUTING and holders(a) == {1: (CLAIMED, "b")}


def test_a_robot_reports_where_and_when_it_is_free_only_when_that_changes(line_graph, tmp_path):
    a, _ = robots(line_graph, tmp_path)
    decide(a, 1.0)
    decide(a, 2.0)                                       # idle on A since 1 s: nothing new
    assert a.fleet.fleet(2.0)["a"] == (A, 1.0)
    take_in(a, [make_instruction(1, A, duration=30, function=1)], 3.0)
    assert a.mode == EXECUTING and a.fleet.fleet(3.0)["a"] == (A, 33.0)
    fleet_news(a, 4.0)                                   # a tick: the same report holds
    assert a.fleet.fleet(4.0)["a"] == (A, 33.0)


def test_what_another_robot_does_not_claim_in_time_is_taken_after_claim_wait(
        line_graph, tmp_path):
    a, b = robots(line_graph, tmp_path, claim_wait_s=5.0)
    fleet_news(b, 0.0)                                   # b: free on D now, then silent
    take_in(a, [make_instruction(1, D, duration=4, function=1)], 0.0)
    assert decide(a, 4.9) == [] and a.mode == IDLE       # b may still claim it
    decide(a, 5.0)
    assert a.mode == MOVING and a.goal_for == 1 and holders(a)[1] == (CLAIMED, "a")


def test_a_driving_robot_gives_its_claim_back_to_a_robot_now_free_nearer(line_graph, tmp_path):
    a, b = robots(line_graph, tmp_path)
    take_in(b, [make_instruction(9, D, duration=20, function=2)], 0.0)   # b busy until 20 s
    take_in(a, [make_instruction(1, D, gamma=5.0, duration=2, function=1)], 0.0)
    assert a.mode == MOVING and a.goal_for == 1 and holders(a)[1] == (CLAIMED, "a")
    assert free_point(a, 0.0) == (D, pytest.approx(12.0 + 2.0))   # 6 m at 0.5 m/s, then 2 s
    b.executing = (9, 1.0)                               # b's function is over early
    fleet_news(b, 1.0)
    finish(b, 1.0)                                       # and b decides
    assert b.mode == IDLE and holders(b)[1] == (CLAIMED, "a")   # a holds it: b leaves it
    assert redecide(a, 1.5) == []                        # as on news: b serves it sooner
    assert a.fleet.held == 0 and a.goal_for == 0 and a.mode == MOVING   # drives on to B
    assert (1.5, "gave 1 back to the fleet") in a.log and holders(a)[1] == (OPEN, "")
    decide(b, 1.6)
    assert b.mode == EXECUTING and b.executing[0] == 1 and holders(a)[1] == (CLAIMED, "b")


def test_a_robot_executing_keeps_its_instruction(line_graph, tmp_path):
    a, b = robots(line_graph, tmp_path)
    take_in(a, [make_instruction(1, A, duration=30, function=1)], 0.0)
    assert a.mode == EXECUTING
    fleet_news(b, 1.0)                                   # b knows it, free on D
    assert redecide(a, 2.0) == [] and a.mode == EXECUTING and a.fleet.held == 1
    assert decide(b, 2.0) == [] and b.mode == IDLE and holders(a)[1] == (CLAIMED, "a")


def test_two_robots_on_the_auction_serve_every_instruction_once(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    arrivals = [(t, 0 if k % 2 else 1, make_instruction(k + 1, (A, B, D, B, A, D)[k],
                                                         gamma=3.0, duration=3, function=1))
                for k, t in enumerate((0.0, 0.0, 1.0, 5.0, 6.0, 12.0))]
    run_executor_fleet([a, b], arrivals, NavigationModel(line_graph, 0.5), until_s=200.0)
    got = served([a, b])
    assert sorted(got) == [1, 2, 3, 4, 5, 6] and all(len(v) == 1 for v in got.values())
    assert {robot for v in got.values() for robot, _ in v} == {"a", "b"}


def test_a_per_robot_allocator_keeps_the_robots_own_planner(line_graph, tmp_path):
    a, _ = robots(line_graph, tmp_path, fleet_allocator="seed")
    assert fleet_allocator(a) is None
    with pytest.raises(ValueError, match="unknown fleet allocator 'nope'"):
        fleet(line_graph, tmp_path, starts=(A,), fleet_allocator="nope")


def test_with_the_auction_every_overdue_instruction_stays_eligible(line_graph, tmp_path):
    """On its own a robot keeps to one place among overdue instructions; in a fleet with the
    auction it must not: the auction may give it the one that is not at that place."""
    a, _ = robots(line_graph, tmp_path, serve_within_s=120.0)
    a.buffer.submit_many([make_instruction(1, D, function=1, start_time=0.0),
                          make_instruction(2, B, function=1, start_time=50.0)], 50.0)
    problem, available = fetch_and_decode(a, 200.0)
    assert sorted(int(problem.ids[k]) for k in available) == [1, 2]


def test_with_auction_waiting_an_idle_robot_drives_to_its_waiting_place(line_graph, tmp_path):
    """a on A and b on D, both free with nothing to do: the graph's 2-median is {B, D}
    (fleet_waiting), so a drives to B, without looking around there, and b stays on D."""
    from task_planner.behaviours.driving import arrive
    from task_planner.executor_commands import Navigate
    a, b = robots(line_graph, tmp_path, fleet_allocator="auction_waiting")
    fleet_news(b, 0.0)                                   # b reports: free on D now
    assert decide(a, 0.0) == [Navigate(B, 0)]
    assert a.mode == MOVING and a.log[-1] == (0.0, "wait at B")
    assert decide(b, 0.1) == [] and b.mode == IDLE
    assert arrive(a, 2.0) == [] and (a.node, a.mode) == (B, IDLE)


def test_with_auction_waiting_a_robot_hearing_from_no_other_waits_a_renew_period(line_graph,
                                                                                 tmp_path):
    """Started together, a sees only itself until b's first report: it stays on A instead of
    deciding alone at once. Once b reports from D, a drives to its place of the 2-median, B.
    Hearing from nobody a whole renew period (b gone), a decides alone: the 1-median of
    A-B-C-D (1, 2 and 3 m), B (8 m to all, as C; the first)."""
    from task_planner.executor_commands import Navigate
    a, b = robots(line_graph, tmp_path, fleet_allocator="auction_waiting")
    assert decide(a, 0.0) == [] and a.mode == IDLE
    fleet_news(b, 0.5)                                   # b's first report: free on D
    assert decide(a, 1.0) == [Navigate(B, 0)] and a.alone_since is None
    (tmp_path / "alone").mkdir()
    alone, _ = robots(line_graph, tmp_path / "alone", fleet_allocator="auction_waiting")
    period = alone.fleet.renew_period_s
    assert decide(alone, 0.0) == [] and decide(alone, period - 0.1) == []
    assert decide(alone, period) == [Navigate(B, 0)] and alone.log[-1] == (period, "wait at B")


def test_with_auction_waiting_a_robot_keeps_its_waiting_place_while_the_fleet_size_holds(
        line_graph, tmp_path):
    """a on C, b on D: matched to the 2-median {B, D} by least travel, a takes B (2 m) and b D.
    b's next report puts it on A (a report older than b's move, say): a new matching would send
    a to D (3 + 1 m against 2 + 6 m), but a keeps B until it serves again."""
    from task_planner.executor_commands import Navigate
    a, b = robots(line_graph, tmp_path, fleet_allocator="auction_waiting")
    a.node = C
    fleet_news(b, 0.0)
    assert decide(a, 0.0) == [Navigate(B, 0)] and a.waiting_for == (("a", "b"), B)
    b.node = A
    fleet_news(b, 1.0)
    a.mode = IDLE
    assert decide(a, 1.0) == [Navigate(B, 0)] and a.waiting_for == (("a", "b"), B)


def test_a_robot_driving_to_its_waiting_place_reports_that_place(line_graph, tmp_path):
    """a on A drives to its waiting place B; had it stood at C, it would report B all the same:
    the other robots match on where it will wait, not on the next node of its way."""
    a, b = robots(line_graph, tmp_path, fleet_allocator="auction_waiting")
    fleet_news(b, 0.0)
    decide(a, 0.0)
    assert a.mode == MOVING and free_point(a, 0.0) == (B, 2.0)    # 1 m at 0.5 m/s
    a.node = C
    assert free_point(a, 1.0) == (B, 5.0)



def test_a_kept_waiting_place_another_robot_reports_itself_at_is_matched_afresh(line_graph,
                                                                                tmp_path):
    """a keeps B; b then reports itself free at B: a matches again on the pool's table, where
    both will be at B, and keeps B as the first name; b, matching on the same table, takes D
    (the other place of the 2-median)."""
    from task_planner.executor_commands import Navigate
    a, b = robots(line_graph, tmp_path, fleet_allocator="auction_waiting")
    fleet_news(b, 0.0)
    assert decide(a, 0.0) == [Navigate(B, 0)]
    b.node = B
    b.fleet.report(B, 1.0, 1.0)
    a.mode = IDLE
    assert decide(a, 1.0) == [Navigate(B, 0)] and a.waiting_for == (("a", "b"), B)
    b.mode = IDLE
    assert decide(b, 1.0) == [Navigate(C, 0)] and b.waiting_for == (("a", "b"), D)


def test_a_waiting_place_out_of_reach_is_not_driven_to_again_for_corridor_wait(line_graph,
                                                                              tmp_path):
    """a drives from A to its waiting place B and gives up (something blocks B): matched
    afresh, it gets B again, and waits on A instead of bumping into the block every tick; after
    corridor_wait_s it tries again."""
    from task_planner.behaviours.recovery import recover
    from task_planner.executor_commands import Navigate
    a, b = robots(line_graph, tmp_path, fleet_allocator="auction_waiting")
    fleet_news(b, 0.0)
    assert decide(a, 0.0) == [Navigate(B, 0)]
    a.attempts = a.config.max_goal_attempts
    recover(a, 3.0, "blocked")
    assert a.mode == IDLE and a.wait_given_up == (B, 3.0) and a.node == A
    wait = a.config.corridor_wait_s
    assert decide(a, 4.0) == [] and decide(a, 3.0 + wait - 0.1) == [] and a.mode == IDLE
    fleet_news(b, 3.0 + wait)                            # b still free on D
    assert decide(a, 3.0 + wait) == [Navigate(B, 0)]
