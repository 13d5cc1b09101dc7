"""A damaged task buffer journal or fleet pool (SQLite or PostgreSQL): every row that does not
load is quarantined with its reason, the others load, and the buffer or pool keeps working (no
TypeError or IndexError)."""
import json
import sqlite3

import pytest
from planner_factories import POOL_BACKENDS, execute_in_pool, make_instruction

from task_planner.fleet_pool import FleetPool, LeaseLost
from task_planner.task_buffer import DONE, FAILED, PENDING, BufferConfig, TaskBuffer

CONFIG = BufferConfig(node_count=9, functions=((1, "chat"), (5, "remind")))
DAMAGE = {   # id -> (SQL that damages row id, the reason's end)
    2: ("UPDATE instructions SET gamma = NULL WHERE id = 2", "column gamma is NULL, not a number"),
    3: ("UPDATE instructions SET gamma = 'high' WHERE id = 3",
        "column gamma holds text 'high', not a number"),
    4: ("UPDATE instructions SET state = 7 WHERE id = 4",
        "column state holds 7, not a state (0 pending, 1 active, 2 done, 3 failed, "
        "4 cancelled)"),
    5: ("UPDATE instructions SET destination = 99 WHERE id = 5",
        "instruction 5: destination node 99 is not in the graph (nodes 0..8)"),
    6: ("UPDATE instructions SET function = 99 WHERE id = 6",
        "instruction 6: function 99 is no robot function (known: 1 chat, 5 remind)"),
    7: ("UPDATE instructions SET text = X'00ff10' WHERE id = 7",
        "column text holds a BLOB (3 bytes), not text"),
    8: ("UPDATE instructions SET duration = 2.5 WHERE id = 8",
        "column duration holds 2.5, not an integer"),
}


def _damaged(path, ids):
    buffer = TaskBuffer(path, CONFIG)
    for i in range(1, 10):
        buffer.submit(make_instruction(i, 2, function=5, text="remind Ann"), now=1.0)
    buffer.close()
    with sqlite3.connect(path) as db:
        for i in ids:
            db.execute(DAMAGE[i][0])
    return path


@pytest.mark.parametrize("row", sorted(DAMAGE))
def test_a_row_that_does_not_load_is_quarantined_with_its_reason(tmp_path, row):
    buffer = TaskBuffer(_damaged(tmp_path / "journal.sqlite", [row]), CONFIG)
    reason = f"quarantined: journal row {row} is no valid instruction: {DAMAGE[row][1]}"
    assert buffer.quarantined == [(row, reason)]
    assert [r.instruction.id for r in buffer.open_records()] == [i for i in range(1, 10)
                                                                 if i != row]
    assert buffer.next_id() == 10   # its id stays used
    buffer.close()


def test_open_quarantined_rows_are_failed_and_the_buffer_serves_new_ones(tmp_path):
    path = _damaged(tmp_path / "journal.sqlite", sorted(DAMAGE))
    buffer = TaskBuffer(path, CONFIG)
    assert [i for i, _ in buffer.quarantined] == sorted(DAMAGE)
    assert [r.instruction.id for r in buffer.open_records()] == [1, 9]
    new = buffer.submit(make_instruction(buffer.next_id(), 3, function=1), now=2.0)
    assert (new.instruction.id, new.state, new.seq) == (10, PENDING, 10)
    buffer.start(10, now=3.0)
    assert buffer.finish(10, now=4.0).state == DONE
    buffer.close()
    with sqlite3.connect(path) as db:
        rows = dict(db.execute("SELECT id, state FROM instructions WHERE id IN (2, 3, 5, 6, 7, 8)"))
        unknown = db.execute("SELECT state FROM instructions WHERE id = 4").fetchone()[0]
    assert rows == {i: FAILED for i in (2, 3, 5, 6, 7, 8)}
    assert unknown == 7   # not open: left as it is, still left out
    again = TaskBuffer(path, CONFIG)
    assert [i for i, _ in again.quarantined] == sorted(DAMAGE)
    assert [r.instruction.id for r in again.open_records()] == [1, 9]
    again.close()


def test_a_text_seq_does_not_stop_the_next_seq(tmp_path):
    path = tmp_path / "journal.sqlite"
    _damaged(path, [])
    with sqlite3.connect(path) as db:
        db.execute("UPDATE instructions SET seq = 'x' WHERE id = 9")
    buffer = TaskBuffer(path, CONFIG)
    assert buffer.quarantined == [(9, "quarantined: journal row 9 is no valid instruction: "
                                      "column seq holds text 'x', not an integer")]
    assert buffer.submit(make_instruction(10, 1, function=1), now=2.0).seq == 9
    buffer.close()


def _with(**fields):
    """The damage: a pool row's instruction (JSON) with `fields` set."""
    return lambda text: json.dumps({**json.loads(text), **fields})


POOL_DAMAGE = {   # id -> (the damage to the row's instruction text, the reason's end)
    2: (lambda _: "not json", "column instruction holds 'not json', not an instruction in JSON "
                              "(Expecting value: line 1 column 1 (char 0))"),
    3: (_with(gamma=None), "field gamma is NULL, not a number"),
    4: (_with(gamma="high"), "field gamma holds text 'high', not a number"),
    5: (_with(colour="red"), "unknown field(s) colour"),
    6: (_with(beta=2.0), "instruction 6: beta must lie in [0.01, 1) (Eq. 4-2); got beta = 2.0"),
    7: (lambda _: b"\x00\xff\x10",   # a BLOB: SQLite only (PostgreSQL's column holds text)
        "column instruction holds b'\\x00\\xff\\x10', not an instruction in JSON ('utf-8' codec "
        "can't decode byte 0xff in position 1: invalid start byte)"),
    8: (lambda _: "[1, 2]", "holds list [1, 2], not an instruction's fields"),
}


@pytest.mark.parametrize("pool_url, row", [
    (backend, row) for backend in POOL_BACKENDS for row in sorted(POOL_DAMAGE)
    if backend == "sqlite" or row != 7], indirect=["pool_url"])
def test_a_fleet_pool_row_that_does_not_load_is_skipped_with_its_reason(pool_url, row):
    pool = FleetPool(pool_url)
    pool.share([make_instruction(i, 2) for i in range(1, 10)])
    execute_in_pool(pool_url, "UPDATE pool SET instruction = ? WHERE id = ?",
                    (POOL_DAMAGE[row][0](pool._shared(row)), row))
    seq, shared = pool.since(0)
    assert seq == 9 and [i.id for i in shared] == [i for i in range(1, 10) if i != row]
    assert pool.quarantined == {row: f"quarantined: fleet pool row {row} is no valid "
                                     f"instruction: {POOL_DAMAGE[row][1]}"}
    assert pool.next_id() == 10 and pool.claim("a", 9, 0.0)   # the pool goes on
    pool.close()


def test_a_damaged_fleet_pool_row_state_or_id_counter_does_not_stop_the_pool(pool_url):
    pool = FleetPool(pool_url)
    pool.share([make_instruction(i, 2) for i in (1, 2)])
    assert pool.next_id() == 3
    execute_in_pool(pool_url, "UPDATE pool SET state = 9 WHERE id = 1")
    on_sqlite = not pool_url.startswith("postgresql://")   # PostgreSQL's columns keep their type
    if on_sqlite:   # a counter that is no number is left out: ids go on from the largest shared
        execute_in_pool(pool_url, "UPDATE pool_ids SET last = 'x'")
    assert pool.next_id() == (3 if on_sqlite else 4)
    with pytest.raises(LeaseLost, match="instruction 1 .*: in the unknown state 9"):
        pool.complete("a", 1, 0.0)
    pool.close()
