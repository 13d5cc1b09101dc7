"""A damaged human database: a person's row that does not load is quarantined with its reason,
get refuses it by name, and everyone else is served (no TypeError at start or per request)."""
import sqlite3

import pytest
from human_factories import make_human

from human_db.errors import InvalidHuman
from human_db.store import HumanStore

# SQL that damages Bob's row (his id is 2) -> the reason's end. A value its column's CHECK
# refuses (age 'old', a colour 'red') makes PRAGMA quick_check refuse the whole file instead.
DAMAGE = {
    "UPDATE humans SET name = X'00ff' WHERE id = 2": "column name holds b'\\x00\\xff', not text",
    "UPDATE humans SET location = X'01' WHERE id = 2": "column location holds b'\\x01', not text",
    "UPDATE humans SET last_seen = 'yesterday' WHERE id = 2":
        "column last_seen holds 'yesterday', not a time",
    "UPDATE humans SET age = 200 WHERE id = 2":
        "human 'Bob': age must be an integer in 0-150, got 200",
    "UPDATE humans SET ip = 'not-an-ip' WHERE id = 2":
        "human 'Bob': 'not-an-ip' is not an IP address",
    "UPDATE schedules SET start_s = 'nine' WHERE human_id = 2":
        "schedules row 1: column start_s holds 'nine', not a number",
}


@pytest.fixture
def path(tmp_path, alice):
    path = tmp_path / "humans.sqlite"
    store = HumanStore(path)
    bob = make_human("Bob", "192.168.1.102", ((35, 70, 190),) * 3, gender="male", age=37,
                     schedules=alice.schedules[:1])
    store.register_all([make_human("Alice"), bob, make_human("Carol", "192.168.1.103")], now=1.0)
    store.close()
    return path


def _damage(path, statement):
    with sqlite3.connect(path) as db:
        db.execute(statement)


@pytest.mark.parametrize("statement", sorted(DAMAGE))
def test_a_row_that_does_not_load_is_quarantined_and_the_others_served(path, statement):
    _damage(path, statement)
    store = HumanStore(path)
    assert [h.name for h in store.humans()] == ["Alice", "Carol"]
    name = "b'\\x00\\xff'" if "X'00ff'" in statement else "'Bob'"
    assert store.quarantined == {2: f"quarantined: {store.path}: humans row 2 ({name}) does not "
                                    f"load: {DAMAGE[statement]}"}
    assert store.shirt_colour_table()[0] == ["Alice", "Carol"]
    assert store.get("Carol").name == "Carol"
    store.close()


def test_get_refuses_a_quarantined_person_naming_why_and_replacing_repairs_the_row(path):
    _damage(path, "UPDATE humans SET last_seen = 'yesterday' WHERE id = 2")
    store = HumanStore(path)
    with pytest.raises(InvalidHuman, match=r"humans row 2 \('Bob'\) does not load: column "
                                           "last_seen holds 'yesterday', not a time"):
        store.get("Bob")
    store.humans()
    assert list(store.quarantined) == [2]
    store.register(make_human("Bob", "192.168.1.102", gender="male"), replace=True, now=2.0)
    assert [h.name for h in store.humans()] == ["Alice", "Bob", "Carol"]
    assert store.quarantined == {}
    store.close()
