"""A robot of a fleet that restarts, loses its journal or fails a pool write rejoins from its
journal (FleetLink.rejoin): nothing it journalled is lost to the fleet, nothing it held is kept
alive, nothing closed is served again. The tests of the link and the pool alone run on SQLite
and PostgreSQL (`pool_url`)."""
import sqlite3

import pytest
from planner_factories import make_instruction
from test_executor_fleet import A, B, C, D, FUNCTIONS, fleet, robot, served

from task_planner.battery import BatteryConfig, BatteryModel
from task_planner.executor import Charging
from task_planner.executor_commands import MOVING, StopMotion
from task_planner.executor_sim import NavigationModel, run_executor_fleet
from task_planner.fleet_link import FleetLink
from task_planner.graph import graph_from_edges
from task_planner.fleet_pool import CANCELLED, CLAIMED, DONE, FAILED, FleetPool
from task_planner.reward import Priority
from task_planner import task_buffer
from task_planner.task_buffer import BufferConfig, TaskBuffer


def test_a_restarted_robot_still_charges_its_own_body(line_graph, tmp_path):
    config = BatteryConfig(capacity_wh=0.1, idle_w=0.0, moving_w=0.0, executing_w=0.0,
                           charge_w=36.0, low_fraction=0.5)

    def charging():
        battery = BatteryModel(config)
        battery.level_wh = 0.02          # low: 20 % (the journalled level wins at a restart)
        return Charging(battery, A, 8, Priority("self_generated", 1.0, 0.9))

    first = robot(line_graph, tmp_path, "a", D, charging=charging())
    first.tick(0.0)                      # low: it gives itself a charge instruction, drives
    [charge] = first.buffer.open_records()
    assert first.mode == MOVING and first.fleet.pool.entries() == []   # never shared
    first.buffer.close()
    again = robot(line_graph, tmp_path, "a", D, charging=charging())   # killed and restarted
    run_executor_fleet([again], [], NavigationModel(line_graph, 0.5), until_s=120.0)
    record = again.buffer.get(charge.instruction.id)
    assert (record.state, record.reason) == (task_buffer.DONE, "")
    assert FUNCTIONS[8].name == "charge" and again.fleet.pool.entries() == []


def test_a_restarted_robot_gives_back_its_claims_and_corridors_at_once(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    before = FleetLink(pool, "a")
    before.share([make_instruction(1, A), make_instruction(2, B)])
    assert before.claim(1, 0.0) and before.enter({"hall"}, 0.0) == ""
    after = FleetLink(FleetPool(pool_url, lease_s=10.0), "a")
    assert after.rejoin([], own=lambda instruction: False) == {}
    assert pool.claimable(1.0) == [1, 2] and pool.enter("b", ["hall"], 1.0) == ""


def test_renewing_keeps_alive_only_what_the_link_holds(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    link = FleetLink(pool, "a")
    link.share([make_instruction(1, A), make_instruction(2, B)])
    assert pool.claim("a", 2, 0.0) and pool.enter("a", ["hall"], 0.0) == ""  # an earlier run's
    assert link.claim(1, 0.0) and link.enter({"alley"}, 0.0) == ""
    link.renew(5.0)
    assert pool.claimable(12.0) == [2]                   # 1 renewed until 15 s, 2 not
    assert pool.enter("b", ["hall"], 12.0) == "" and pool.enter("b", ["alley"], 12.0) == "a"


def test_choosing_its_own_instruction_gives_back_the_one_it_held(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    mine, other = FleetLink(pool, "a"), FleetLink(pool, "b")
    mine.share([make_instruction(8, B)])
    mine.keep_local(7)
    assert mine.claim(8, 0.0) and mine.claim(7, 1.0)
    assert mine.held == 0 and other.claim(8, 1.0)
    assert not mine.holds(8, 2.0) and mine.held == 0


def test_leaving_gives_up_a_corridor_the_link_does_not_remember(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    assert pool.enter("a", ["hall"], 0.0) == ""          # held by the robot's earlier run
    FleetLink(pool, "a").leave()
    assert pool.enter("b", ["hall"], 1.0) == ""


def test_an_instruction_journalled_before_a_failed_share_reaches_the_fleet(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    a.tick(0.0)                                          # joined the fleet
    share = a.fleet.pool.share

    def disk_error(instructions):
        monkeypatch.setattr(a.fleet.pool, "share", share)   # fails once
        raise sqlite3.OperationalError("disk I/O error")

    monkeypatch.setattr(a.fleet.pool, "share", disk_error)
    near_b = make_instruction(1, D, gamma=3.0, beta=0.9, duration=4, function=2)
    with pytest.raises(sqlite3.OperationalError, match="disk I/O error"):
        a.receive([near_b], 0.0)
    assert a.buffer.holds(1) and a.fleet.pool.entries() == []   # journalled, not shared
    run_executor_fleet([a, b], [], NavigationModel(line_graph, 0.5), until_s=60.0)
    # a rejoins at its first tick and shares 1; the auction gives it to b, on D: served once
    got = served([a, b])
    assert list(got) == [1] and len(got[1]) == 1 and a.buffer.get(1).reason == "done by b"


def test_a_restarted_robot_shares_what_it_journalled_but_never_shared(line_graph, tmp_path):
    journal = TaskBuffer(tmp_path / "a.sqlite", BufferConfig(node_count=line_graph.size))
    journal.submit(make_instruction(5, C, function=1), 0.0)   # killed before it shared it
    journal.close()
    a = robot(line_graph, tmp_path, "a", A)
    a.tick(0.0)                                                # rejoins at its first event
    assert [(e.id, e.state) for e in a.fleet.pool.entries()] == [(5, CLAIMED)]   # and decides


def test_what_a_journal_closed_before_the_pool_learnt_is_closed_at_restart(line_graph, tmp_path):
    pool = FleetPool(tmp_path / "pool.sqlite", lease_s=10.0)
    done, failed = make_instruction(1, B, function=1), make_instruction(2, C, function=1)
    pool.share([done, failed])
    assert pool.claim("a", 1, 0.0)
    journal = TaskBuffer(tmp_path / "a.sqlite", BufferConfig(node_count=line_graph.size))
    journal.submit_many([done, failed], 0.0)
    journal.start(1, 1.0)
    journal.finish(1, 3.0)                    # killed before it closed 1 in the pool
    journal.fail(2, 4.0, "no path")           # 2 was open in the pool
    journal.close()
    robot(line_graph, tmp_path, "a", A).tick(5.0)
    assert [(e.id, e.state, e.robot, e.completion_time) for e in pool.entries()] == [
        (1, DONE, "a", 3.0), (2, FAILED, "a", 4.0)]
    assert not pool.claim("b", 1, 20.0)       # its lease has run out, but it is served


def test_a_robot_whose_journal_was_lost_serves_nothing_again(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    here = make_instruction(1, A, gamma=5.0, beta=0.9, duration=4, function=1)
    run_executor_fleet([a, b], [(0.0, 0, here)], NavigationModel(line_graph, 0.5))
    a.buffer.close()
    for path in tmp_path.glob("a.sqlite*"):
        path.unlink()
    again = robot(line_graph, tmp_path, "a", A)
    traces = run_executor_fleet([again], [], NavigationModel(line_graph, 0.5), until_s=60.0)
    record = again.buffer.get(1)
    assert (record.state, record.reason) == (task_buffer.DONE, "done by a")
    assert traces[0].executed == [] and served([again]) == {}


def test_a_chain_closed_in_the_pool_closes_each_instruction_once(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    head = make_instruction(1, C, function=1)
    then = make_instruction(2, C, function=2, previous_id=1)
    a.receive([head, then], 0.0)
    b.tick(0.0)                                        # b takes both in
    a.fleet.close(1, 1.0, FAILED)
    a.fleet.pool.settle("a", 2, 1.0, FAILED)           # as a rejoin after a restart does
    b.tick(2.0)                                        # both closed in the pool: no error
    assert [(r.state, r.reason) for r in b.buffer.records()] == [
        (task_buffer.FAILED, "failed by a"), (task_buffer.FAILED, "predecessor 1 failed")]


def test_a_move_serves_the_instruction_the_robot_claimed(line_graph, tmp_path):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    slow = make_instruction(1, C, gamma=1.0, beta=0.99, duration=60, function=1)
    a.receive([slow], 0.0)
    assert (a.mode, a.goal, a.state.goal_for) == (MOVING, B, 1)
    urgent = make_instruction(2, D, gamma=9.0, beta=0.9, duration=4, function=2, start_time=1.0)
    a.receive([urgent], 1.0)                           # mid-edge; D lies through B too
    assert (a.mode, a.goal, a.state.goal_for, a.fleet.held) == (MOVING, B, 2, 2)
    assert a.fleet.pool.claimable(1.0) == [1]


def test_a_cancelled_instruction_is_closed_in_the_pool_before_it_is_given_back(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    a.receive([make_instruction(1, A, duration=10, function=1)], 0.0)   # executing at once
    calls = []
    for name in ("cancel", "release"):
        method = getattr(a.fleet.pool, name)
        monkeypatch.setattr(a.fleet.pool, name, lambda *args, name=name, method=method: (
            calls.append(name), method(*args))[1])
    a.cancel(1, 1.0)
    assert calls == ["cancel"]
    assert [(e.state, e.robot) for e in a.fleet.pool.entries()] == [(CANCELLED, "a")]


def failing_once(monkeypatch, pool, name, error="disk I/O error"):
    """Make the pool's `name` raise sqlite3.OperationalError(error) at its next call only."""
    method = getattr(pool, name)

    def fail(*args):
        monkeypatch.setattr(pool, name, method)
        raise sqlite3.OperationalError(error)

    monkeypatch.setattr(pool, name, fail)


def test_a_failed_pool_write_never_gives_back_what_the_robot_executes(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    long_one = make_instruction(1, A, gamma=5.0, beta=0.99, duration=30, function=1)
    a.receive([long_one], 0.0)                           # executes 1 until 30 s
    b.tick(0.0)
    failing_once(monkeypatch, a.fleet.pool, "share")
    with pytest.raises(sqlite3.OperationalError):
        a.receive([make_instruction(2, C, function=1)], 1.0)
    traces = run_executor_fleet([a, b], [], NavigationModel(line_graph, 0.5), until_s=120.0)
    # a rejoins at its next tick holding 1 still; b never takes it and serves 2
    assert [i for _, i, _ in traces[1].executed] == [2]
    assert served([a, b])[1] == [("a", pytest.approx(5 * 0.99 ** 30))]


def test_a_fault_in_a_tick_rejoins_and_settles_what_the_journal_finished(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    a.receive([make_instruction(1, A, gamma=5.0, beta=0.99, duration=4, function=1)], 0.0)
    b.receive([make_instruction(9, D, duration=20, function=2)], 0.0)   # b is busy
    failing_once(monkeypatch, a.fleet.pool, "complete", "database is locked")
    with pytest.raises(sqlite3.OperationalError):
        a.tick(4.0)                                      # journalled DONE, the pool not told
    a.fault(4.0, "database is locked")                   # as the node's fault handler does
    traces = run_executor_fleet([a, b], [], NavigationModel(line_graph, 0.5), until_s=120.0)
    assert [i for _, i, _ in traces[1].executed] == []  # b never serves 1 again
    entries = {e.id: (e.state, e.robot) for e in a.fleet.pool.entries()}
    assert entries[1] == (DONE, "a")


def test_an_id_the_fleet_knows_as_another_instruction_is_failed_not_served(
        line_graph, tmp_path):
    theirs = make_instruction(5, C, gamma=3.0, function=2)
    pool = FleetPool(tmp_path / "pool.sqlite", lease_s=10.0)
    pool.share([theirs])                                 # b received it
    journal = TaskBuffer(tmp_path / "a.sqlite", BufferConfig(node_count=line_graph.size))
    journal.submit(make_instruction(5, A, function=1), 0.0)   # a's, never shared
    journal.close()
    a, b = robot(line_graph, tmp_path, "a", A), robot(line_graph, tmp_path, "b", D)
    traces = run_executor_fleet([a, b], [], NavigationModel(line_graph, 0.5), until_s=120.0)
    mine = a.buffer.get(5)
    assert mine.state == task_buffer.FAILED and mine.reason.startswith(
        "not served: instruction 5: the fleet pool holds another instruction under this id")
    assert traces[0].executed == []                     # a serves neither
    assert [(i, name) for _, i, name in traces[1].executed] == [(5, "encourage")]


def test_rejoining_is_one_transaction_for_the_other_robots(line_graph, tmp_path):
    """A robot killed after it finished 1 but before the pool heard of it: while it rejoins,
    the other robot cannot claim 1 in between giving back and settling."""
    pool_b = FleetPool(tmp_path / "pool.sqlite", lease_s=10.0)
    pool_b._db.run("PRAGMA busy_timeout=50")              # b gives up quickly
    done = make_instruction(1, B, function=1)
    pool_b.share([done])
    assert pool_b.claim("a", 1, 0.0)
    journal = TaskBuffer(tmp_path / "a.sqlite", BufferConfig(node_count=line_graph.size))
    journal.submit(done, 0.0)
    journal.start(1, 1.0)
    journal.finish(1, 3.0)
    records = journal.records()
    journal.close()
    link = FleetLink(FleetPool(tmp_path / "pool.sqlite", lease_s=10.0), "a")
    entries, tries = link.pool.entries, []

    def entries_while_b_tries():
        try:
            tries.append(pool_b.claim("b", 1, 4.0))
        except sqlite3.OperationalError as error:
            tries.append(str(error))
        return entries()

    link.pool.entries = entries_while_b_tries
    assert link.rejoin(records, own=lambda instruction: False, now=4.0) == {}
    assert tries == ["database is locked"]
    assert [(e.state, e.robot) for e in pool_b.entries()] == [(DONE, "a")]


def test_no_robot_claims_what_a_rejoining_robot_gives_back_and_claims_again(pool_url):
    """Between giving back its earlier run's claims and claiming again what it serves, the
    rejoin's transaction holds the instruction: SQLite locks the pool, PostgreSQL the row (a
    claim skips a locked row)."""
    pool_b = FleetPool(pool_url, lease_s=10.0)
    on_sqlite = not pool_url.startswith("postgresql://")
    if on_sqlite:
        pool_b._db.run("PRAGMA busy_timeout=50")          # b gives up quickly
    serving = make_instruction(1, B, function=1)
    pool_b.share([serving])
    assert pool_b.claim("a", 1, 0.0)
    link = FleetLink(FleetPool(pool_url, lease_s=10.0), "a")
    claim, tries = link.pool.claim, []

    def claim_after_b_tried(*args):
        try:                                              # 1 is given back (open) by now
            tries.append(pool_b.claim("b", 1, 4.0))
        except sqlite3.OperationalError as error:
            tries.append(str(error))
        return claim(*args)

    link.pool.claim = claim_after_b_tried
    assert link.rejoin([], own=lambda instruction: False, keep=1, now=4.0) == {}
    assert tries == (["database is locked"] if on_sqlite else [False])
    assert link.held == 1 and [(e.state, e.robot, e.lease_until) for e in pool_b.entries()] == [
        (CLAIMED, "a", 14.0)]


def test_a_restarted_robot_holds_the_corridor_it_stands_in(star_graph, tmp_path):
    H = 0
    a = robot(star_graph, tmp_path, "a", H, corridors=(H,))
    b = robot(star_graph, tmp_path, "b", 1, corridors=(H,))
    a.tick(0.0)
    assert b.fleet.enter({"H"}, 1.0) == "a"


def test_a_clashing_id_failed_here_never_closes_the_other_robots_instruction(
        line_graph, tmp_path):
    pool = FleetPool(tmp_path / "pool.sqlite", lease_s=10.0)
    pool.share([make_instruction(5, C, gamma=3.0, function=2)])      # b's
    journal = TaskBuffer(tmp_path / "a.sqlite", BufferConfig(node_count=line_graph.size))
    journal.submit(make_instruction(5, A, function=1), 0.0)          # a's, never shared
    journal.close()
    a = robot(line_graph, tmp_path, "a", A)
    a.tick(0.0)                                          # fails its 5 here
    a.fault(1.0, "database is locked")                   # a later rejoin ...
    a.tick(1.25)
    assert [(e.id, e.state) for e in pool.entries()] == [(5, 0)]   # ... leaves b's 5 open


def test_a_robot_stops_serving_what_another_robot_took_while_it_was_out_of_step(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    far = make_instruction(1, C, gamma=3.0, beta=0.99, duration=4, function=1)
    a.receive([far], 0.0)                                # a claims 1 and drives A -> B
    assert (a.mode, a.state.goal_for) == (MOVING, 1)
    b.tick(11.0)                                         # a's lease ran out: b takes 1
    assert b.fleet.held == 1
    failing_once(monkeypatch, a.fleet.pool, "share")
    with pytest.raises(sqlite3.OperationalError):
        a.receive([make_instruction(2, A, function=2)], 11.5)
    commands = a.tick(11.75)                             # rejoins: 1 is b's now
    assert a.mode != MOVING or a.state.goal_for != 1
    assert StopMotion() in commands
    assert (11.75, "lost 1 to another robot") in a.log
    assert a.buffer.get(1).is_open                       # b serves it, not failed here


def test_rejoining_keeps_the_corridor_the_robot_drives_into(star_graph, tmp_path, monkeypatch):
    H, L1 = 0, 1
    a = robot(star_graph, tmp_path, "a", L1, corridors=(H,))
    b = robot(star_graph, tmp_path, "b", 2, corridors=(H,))
    a.receive([make_instruction(1, 3, function=1)], 0.0)   # a drives L1 -> H
    assert (a.mode, a.goal) == (MOVING, H) and a.fleet.corridors == {"H"}
    failing_once(monkeypatch, a.fleet.pool, "share")
    with pytest.raises(sqlite3.OperationalError):
        a.receive([make_instruction(2, 2, function=2)], 1.0)
    a.tick(1.25)                                          # rejoins while driving into H
    assert b.fleet.enter({"H"}, 2.0) == "a"


def test_an_arrival_out_of_step_never_serves_the_fleets_other_instruction_under_its_id(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    b.receive([make_instruction(9, D, duration=60, function=2)], 0.0)      # b is busy
    a.receive([make_instruction(7, C, gamma=1.0, beta=0.9, duration=2, function=2)], 0.1)
    failing_once(monkeypatch, a.fleet.pool, "share")
    with pytest.raises(sqlite3.OperationalError):                           # a's 5: journal only
        a.receive([make_instruction(5, A, gamma=50.0, beta=0.99, duration=4, function=1)], 0.5)
    b.receive([make_instruction(5, C, gamma=3.0, duration=4, function=3)], 0.6)   # b's 5
    a.arrived(2.0)                                       # rejoins first: a's 5 fails here
    mine = a.buffer.get(5)
    assert mine.state == task_buffer.FAILED and mine.reason.startswith("not served: ")
    traces = run_executor_fleet([a, b], [], NavigationModel(line_graph, 0.5), until_s=200.0)
    assert 5 not in [i for _, i, _ in traces[0].executed]
    assert b.buffer.get(5).reason == ""                  # b served its own 5
    assert 5 in [i for _, i, _ in traces[1].executed]


def test_a_robot_keeps_the_corridor_it_stands_in_while_the_next_one_is_taken(
        tmp_path, monkeypatch):
    corridor_graph = graph_from_edges(["A", "H1", "H2", "B"],
                                      [("A", "H1", 2.0), ("H1", "H2", 2.0), ("H2", "B", 2.0)])
    H1, H2 = 1, 2
    b = robot(corridor_graph, tmp_path, "b", H2, corridors=(H1, H2))
    a = robot(corridor_graph, tmp_path, "a", H1, corridors=(H1, H2))
    b.receive([make_instruction(1, H2, duration=100, function=1)], 0.0)   # b stays in H2
    a.receive([make_instruction(2, 3, function=2)], 0.5)                 # a waits in H1
    failing_once(monkeypatch, a.fleet.pool, "share")
    with pytest.raises(sqlite3.OperationalError):
        a.receive([make_instruction(3, 0, function=2)], 1.0)
    a.tick(1.25)                                         # rejoins: H1 again, H2 is b's
    assert a.fleet.corridors == {"H1"} and b.fleet.enter({"H1"}, 1.5) == "a"


def test_a_rejoin_claims_what_the_robot_serves_where_it_serves_it(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D), one_robot_per_place=True)
    a.receive([make_instruction(1, D, gamma=3.0, function=1)], 0.0)       # a drives A -> B
    assert a.fleet.pool.places_held_by_others("b", 0.0) == {D}
    failing_once(monkeypatch, a.fleet.pool, "share")
    with pytest.raises(sqlite3.OperationalError):
        a.receive([make_instruction(2, C, function=2)], 1.0)
    a.tick(1.25)
    assert a.fleet.held == 1 and a.fleet.pool.places_held_by_others("b", 1.25) == {D}


def test_a_stop_of_an_event_that_raised_goes_out_with_the_next_tick(
        line_graph, tmp_path, monkeypatch):
    a, b = fleet(line_graph, tmp_path, starts=(A, D))
    a.receive([make_instruction(1, C, gamma=3.0, beta=0.99, duration=4, function=1)], 0.0)
    b.tick(11.0)                                         # a's lease ran out: b takes 1
    failing_once(monkeypatch, a.fleet.pool, "share")
    with pytest.raises(sqlite3.OperationalError):
        a.receive([make_instruction(2, A, function=2)], 11.5)
    failing_once(monkeypatch, a.buffer, "submit_many")
    with pytest.raises(sqlite3.OperationalError):        # rejoins (a stops), then raises
        a.receive([make_instruction(3, A, function=2)], 11.6)
    assert a.mode != MOVING and StopMotion() in a.tick(11.75)
