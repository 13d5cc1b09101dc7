"""The fleet's shared pool, on SQLite and on PostgreSQL alike (`pool_url`): claims are exclusive
across processes, a dead robot's claims return after its lease, nothing is served twice or lost,
and a PostgreSQL server that restarts only makes the calls in between fail."""
import multiprocessing
import os
import re
import signal
import sqlite3
import time

import psycopg2
import pytest
from planner_factories import execute_in_pool

from task_planner.fleet_pool import (CANCELLED, CLAIMED, DONE, FAILED, FleetPool, FleetPoolError,
                                     LeaseLost, PoolUnavailable)
from task_planner.instruction import Instruction

FORK = multiprocessing.get_context("fork")


def _instructions(ids, **fields):
    return [Instruction(id=i, gamma=1.0, beta=0.99, destination=i % 5, **fields) for i in ids]


def test_a_claim_is_exclusive_until_its_lease_runs_out(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    pool.share(_instructions([1, 2]))
    assert pool.claim("a", 1, now=0.0)
    assert not pool.claim("b", 1, now=5.0)             # a holds it
    assert pool.claimable(5.0) == [2]
    assert pool.renew("a", now=9.0, ids=[1, 2]) == [1]  # held until 19; 2 it never held
    assert not pool.claim("b", 1, now=15.0)
    assert pool.claimable(19.5) == [1, 2]              # a stopped renewing
    assert pool.claim("b", 1, now=19.5)
    with pytest.raises(LeaseLost, match="robot 'a' does not hold instruction 1 .* held by 'b'"):
        pool.complete("a", 1, now=20.0)
    pool.complete("b", 1, now=21.0)
    entry = pool.entries()[0]
    assert (entry.state, entry.robot, entry.completion_time, entry.claims) == (DONE, "b", 21.0, 2)
    assert not pool.claim("a", 1, now=100.0)           # done stays done
    assert pool.renew("a", now=100.0, ids=[1]) == []


def test_released_and_bad_requests(pool_url):
    pool = FleetPool(pool_url, lease_s=1.0)
    pool.share(_instructions([7]))
    assert pool.share(_instructions([7])) == {}        # already there: left as it is
    assert pool.claim("a", 7, 0.0)
    pool.release("a", 7)
    assert pool.claimable(0.1) == [7]
    with pytest.raises(LeaseLost, match="instruction 8 at 0.000 s: not in the pool"):
        pool.complete("a", 8, 0.0)
    with pytest.raises(FleetPoolError, match="non-empty string"):
        pool.claim("", 7, 0.0)
    with pytest.raises(FleetPoolError, match="lease_s must be > 0"):
        FleetPool(":memory:", lease_s=0)


def test_shared_instructions_reach_every_robot_in_order_and_ids_are_the_fleets(pool_url):
    pool = FleetPool(pool_url)
    first = _instructions([3, 1], text="bring water")
    assert pool.share(first) == {}
    seq, seen = pool.since(0)
    assert seen == first                               # as shared, every field kept
    assert pool.since(seq) == (seq, [])
    assert pool.next_id() == 4                         # above every shared id
    assert pool.next_id() == 5                         # handed out, though not shared yet
    assert pool.next_id(above=9) == 10
    later = _instructions([4])
    pool.share(later)
    assert pool.since(seq) == (seq + 1, later)
    other = _instructions([4], text="another request")
    assert pool.share(other) == {4: "instruction 4: the fleet pool holds another instruction "
                                    "under this id (let the fleet choose: id 0)"}
    assert pool.since(seq)[1] == later                 # the first one stays


def test_closing_failing_and_cancelling_are_seen_by_every_robot(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    pool.share(_instructions([1, 2, 3, 4]))
    assert pool.claim("a", 1, 0.0) and pool.claim("a", 2, 0.0) and pool.claim("b", 3, 0.0)
    assert pool.held_by_others("b", 1.0) == {1, 2}
    assert pool.held_by_others("a", 1.0) == {3}
    assert pool.held_by_others("a", 10.5) == set()     # b's lease ran out
    assert pool.claim("a", 2, 0.5, place=4)             # a's own: renewed, now at place 4
    assert pool.places_held_by_others("b", 1.0) == {4}  # 1 was claimed without a place
    assert pool.places_held_by_others("a", 1.0) == set()
    pool.complete("a", 1, 2.0)
    pool.fail("a", 2, 3.0)
    assert pool.cancel("b", 4, 4.0)                    # open: closed for everyone
    assert not pool.cancel("b", 1, 5.0)                # done stays done
    with pytest.raises(LeaseLost, match="instruction 3 .* held by 'b'"):
        pool.fail("a", 3, 5.0)
    closed = pool.closed([1, 2, 3, 4, 99])
    assert {i: (e.state, e.robot) for i, e in closed.items()} == {
        1: (DONE, "a"), 2: (FAILED, "a"), 4: (CANCELLED, "b")}
    assert pool.claimable(20.0) == [3]
    assert len(pool.closed(list(range(1, 1200)))) == 3  # more ids than SQLite binds at once


def test_a_transactions_writes_reach_the_other_robots_together(pool_url):
    mine, theirs = FleetPool(pool_url), FleetPool(pool_url)
    with mine.transaction():
        mine.share(_instructions([1]))
        assert mine.claim("a", 1, 0.0)
        assert theirs.since(0) == (0, [])              # nothing yet
    assert theirs.since(0)[1] == _instructions([1])
    assert theirs.claimable(0.0) == [] and not theirs.claim("b", 1, 0.0)


def test_a_corridor_holds_one_robot_until_it_leaves_or_its_lease_runs_out(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    assert pool.enter("a", ["alley"], 0.0) == ""
    assert pool.enter("b", ["hall", "alley"], 1.0) == "a"   # all or none: not the hall either
    assert pool.enter("c", ["hall"], 1.0) == ""
    assert pool.enter("a", ["alley"], 2.0) == ""             # its own: kept
    pool.renew("a", 9.0, corridors=["alley"])                # held until 19 s
    assert pool.enter("b", ["alley"], 15.0) == "a"
    assert pool.enter("b", ["alley"], 19.5) == ""            # a stopped renewing
    pool.leave("b")
    pool.renew("c", 10.5, corridors=["hall"])                # held until 20.5 s
    pool.leave("c", keep=("hall",))
    assert pool.enter("a", ["alley"], 20.0) == "" and pool.enter("b", ["hall"], 20.0) == "c"


def test_robots_report_where_they_will_be_free_and_drop_out_after_their_lease(pool_url):
    pool = FleetPool(pool_url, lease_s=10.0)
    pool.report("a", node=3, free_at=12.0, now=0.0)
    pool.report("b", node=1, free_at=5.0, now=4.0)
    assert pool.robots(now=9.0) == {"a": (3, 12.0), "b": (1, 5.0)}
    pool.report("a", node=4, free_at=20.0, now=9.0)     # a new report replaces the old one
    assert pool.robots(now=15.0) == {"a": (4, 20.0)}    # b's report ran out at 14
    with pytest.raises(FleetPoolError):
        pool.report("", node=0, free_at=0.0, now=0.0)


def test_a_foreign_file_or_database_is_refused(pool_url):
    execute_in_pool(pool_url, "CREATE TABLE people (name TEXT)")
    with pytest.raises(FleetPoolError, match=f"fleet pool {re.escape(pool_url)}: not a fleet "
                                             r"pool: holds tables \['people'\]"):
        FleetPool(pool_url)


def test_where_the_pool_is_names_its_kind_and_a_password_is_never_shown(tmp_path):
    path = tmp_path / "pool.sqlite"
    assert FleetPool(f"sqlite://{path}").path == str(path)
    with pytest.raises(FleetPoolError, match="sqlite://pool.sqlite: an SQLite URL names an "
                                             "absolute path"):
        FleetPool("sqlite://pool.sqlite")
    with pytest.raises(FleetPoolError, match="mysql://host/fleet: unknown kind of database"):
        FleetPool("mysql://host/fleet")
    with pytest.raises(PoolUnavailable) as refused:   # nobody listens on port 1
        FleetPool("postgresql://robot:secret@127.0.0.1:1/fleet")
    assert str(refused.value).startswith("fleet pool postgresql://robot:***@127.0.0.1:1/fleet: "
                                         "unavailable (")
    assert "secret" not in str(refused.value)


def _claim_everything(path, robot, ids, queue):
    pool = FleetPool(path, lease_s=1000.0)
    queue.put((robot, [i for i in ids if pool.claim(robot, i, now=1.0)]))


def test_processes_racing_for_the_same_ids_never_share_one(pool_url):
    path = pool_url
    ids = list(range(1, 201))
    FleetPool(path).share(_instructions(ids))
    queue = FORK.Queue()
    workers = [FORK.Process(target=_claim_everything, args=(path, f"r{k}", ids[::1 - 2 * (k % 2)],
                                                            queue)) for k in range(4)]
    for w in workers:
        w.start()
    results = dict(queue.get(timeout=60) for _ in workers)
    for w in workers:
        w.join(timeout=10)
    won = [i for got in results.values() for i in got]
    assert sorted(won) == ids                          # every id once, by exactly one robot


def _serve(path, robot, lease_s, service_s, hang_after, log_path):
    """A robot's loop: claim what is claimable, serve it (sleep), complete it; with `hang_after`
    it stops for good after that many claims, holding the last (killed there by the test).
    Events go to the robot's own file, line by line: a multiprocessing queue shared with a
    process killed while writing could stay locked."""
    pool = FleetPool(path, lease_s=lease_s)
    claimed = 0
    with open(log_path, "a", buffering=1) as log:
        while True:
            now = time.time()
            ids = pool.claimable(now)
            if not ids:
                if all(e.state == DONE for e in pool.entries()):
                    return
                time.sleep(0.02)
                continue
            got = next((i for i in ids if pool.claim(robot, i, now)), None)
            if got is None:
                continue
            claimed += 1
            if claimed == hang_after:
                log.write(f"holds {got}\n")
                time.sleep(600)
            time.sleep(service_s)
            pool.complete(robot, got, time.time())
            log.write(f"done {got}\n")


def _events(log_path):
    text = log_path.read_text() if log_path.exists() else ""
    return [(what, int(i)) for what, i in (line.split() for line in text.splitlines())]


def test_a_killed_robots_instruction_is_served_by_the_other_once(pool_url, tmp_path):
    path = pool_url
    ids = list(range(1, 31))
    pool = FleetPool(path, lease_s=0.5)
    pool.share(_instructions(ids))
    logs = {robot: tmp_path / f"{robot}.log" for robot in ("a", "b")}
    a = FORK.Process(target=_serve, args=(path, "a", 0.5, 0.02, 3, logs["a"]))
    b = FORK.Process(target=_serve, args=(path, "b", 0.5, 0.02, None, logs["b"]))
    a.start()
    b.start()
    deadline = time.monotonic() + 30
    while not any(what == "holds" for what, _ in _events(logs["a"])):
        assert time.monotonic() < deadline and a.is_alive(), "robot a never held an instruction"
        time.sleep(0.01)
    held = next(i for what, i in _events(logs["a"]) if what == "holds")
    os.kill(a.pid, signal.SIGKILL)                     # dies holding `held`
    a.join(timeout=10)
    b.join(timeout=60)
    assert b.exitcode == 0
    served = [(robot, i) for robot in logs for what, i in _events(logs[robot]) if what == "done"]
    assert sorted(i for _, i in served) == ids         # each served once, none lost
    assert ("b", held) in served
    entries = {e.id: e for e in pool.entries()}
    assert all(e.state == DONE for e in entries.values())
    assert entries[held].robot == "b" and entries[held].claims == 2
    assert not any(e.state == CLAIMED for e in entries.values())


def test_a_failed_commit_rolls_back_and_never_leaves_the_write_lock_held(pool_url):
    pool = FleetPool(pool_url)
    run = pool._db.run   # a table of another program's, checked at COMMIT
    if not pool_url.startswith("postgresql://"):
        run("PRAGMA foreign_keys=ON")
    run("CREATE TABLE parent (id INTEGER PRIMARY KEY)")
    run("CREATE TABLE child (parent INTEGER REFERENCES parent(id) DEFERRABLE INITIALLY DEFERRED)")
    with pytest.raises((sqlite3.IntegrityError, psycopg2.IntegrityError),
                       match="(?i)foreign key"):
        with pool.transaction():
            pool.share(_instructions([1]))
            run("INSERT INTO child VALUES (1)")
    assert not pool._db.in_transaction
    assert run("SELECT COUNT(*) FROM child").fetchone()[0] == 0
    assert pool.since(0) == (0, [])                    # rolled back with it
    assert pool.share(_instructions([2])) == {} and pool.claim("b", 2, 0.0)
    execute_in_pool(pool_url, "UPDATE pool SET place=3 WHERE id=2")   # another's write goes on


def test_a_restarting_server_fails_the_calls_in_between_and_loses_nothing(pg_cluster):
    url = pg_cluster.create_database()
    pool = FleetPool(url, lease_s=10.0)
    pool.share(_instructions([1, 2]))
    assert pool.claim("a", 1, 0.0)
    lost = f"fleet pool {re.escape(url)}: unavailable \\(.*\\); the next call connects again"
    with pytest.raises(PoolUnavailable, match=lost):
        with pool.transaction():
            pool.share(_instructions([3]))
            pg_cluster.stop()                          # the server restarts mid-transaction
            pg_cluster.start()
            pool.claim("a", 3, 1.0)
    assert pool.since(0)[1] == _instructions([1, 2])   # 3 was rolled back; connected again
    assert pool.claimable(1.0) == [2] and pool.held_by_others("b", 1.0) == {1}
    pg_cluster.stop()
    try:
        with pytest.raises(PoolUnavailable, match=lost):
            pool.claim("b", 2, 2.0)                    # the connection it had
        with pytest.raises(PoolUnavailable, match=f"fleet pool {re.escape(url)}: unavailable "
                                                  "\\(.*\\); connecting again"):
            pool.claim("b", 2, 2.0)                    # a new one, refused while it is down
    finally:
        pg_cluster.start()
    assert pool.claim("b", 2, 3.0) and pool.held_by_others("a", 3.0) == {2}


def test_a_link_reports_on_change_and_within_its_lease_only():
    from task_planner.fleet_link import FleetLink

    class Counting(FleetPool):
        reports = 0

        def report(self, robot, node, free_at, now):
            Counting.reports += 1
            super().report(robot, node, free_at, now)

    link = FleetLink(Counting(":memory:", lease_s=9.0), "a")   # renews every 3 s
    link.report(2, 5.0, now=0.0)
    link.report(2, 5.0, now=1.0)                  # unchanged, within the renew period
    assert Counting.reports == 1
    link.report(3, 5.0, now=1.5)                  # changed
    link.report(3, 5.0, now=4.6)                  # unchanged, but due
    assert Counting.reports == 3
    assert link.fleet(now=5.0) == {"a": (3, 5.0)}
