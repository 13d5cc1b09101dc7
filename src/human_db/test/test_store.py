"""The SQLite store: round trips, history, bad input, WAL, migrations, refusing bad files."""
import dataclasses
import sqlite3
import threading
import time

import pytest
from human_factories import make_human

from human_db import store as store_module
from human_db.colour import ColourIndex
from human_db.errors import (DatabaseUnusable, DuplicateHuman, InvalidColour, InvalidHuman,
                             StoreBusy, UnknownHuman)
from human_db.model import ScheduleEntry
from human_db.schema import MIGRATIONS, SCHEMA_VERSION
from human_db.store import HistoryEntry, HumanStore, StoreConfig


@pytest.fixture
def store(tmp_path):
    store = HumanStore(tmp_path / "db" / "humans.sqlite")
    yield store
    store.close()


def test_register_and_get_round_trip(store, alice, bob):
    store.register_all([alice, bob], now=10.0)
    assert store.get("Alice") == alice
    assert store.get("alice") == alice            # names are case-blind keys
    assert store.get_by_ip("192.168.1.102") == bob
    assert [h.name for h in store.humans()] == ["Alice", "Bob"]
    assert store.count() == 2
    names, colours = store.shirt_colour_table()
    assert names == ["Alice", "Bob"]
    assert colours.shape == (2, 3, 3)
    assert colours[1, 2].tolist() == [35, 70, 190]


def test_initialization_then_recall_on_the_table_5_1_example(store, bob):
    # Table 5-1 (a) is the query image of the Initialization phase, (b) the test image of Recall.
    store.register(bob)
    store.initialize("Query", [(215, 250, 220), (32, 77, 238), (29, 74, 219)], "male", 25)
    index = ColourIndex(*store.shirt_colour_table())
    match = index.identify([(253, 255, 199), (172, 190, 168), (87, 100, 142)])
    assert match.name == "Query"
    assert match.distance == pytest.approx(189.43967, abs=1e-5)
    with pytest.raises(DuplicateHuman):
        store.initialize("Query", [(0, 0, 0)] * 3, "male", 25)


def test_file_is_wal_at_the_latest_schema_version(store):
    connection = sqlite3.connect(store.path)
    assert connection.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    assert connection.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION == 4
    connection.close()


def test_unknown_name_and_ip_are_refused(store, alice):
    store.register(alice)
    with pytest.raises(UnknownHuman, match="no household member named 'Zoe'"):
        store.get("Zoe")
    with pytest.raises(UnknownHuman, match="10.0.0.9"):
        store.get_by_ip("10.0.0.9")
    with pytest.raises(InvalidHuman, match="not an IP address"):
        store.get_by_ip("192.168.1")
    with pytest.raises(UnknownHuman, match="Zoe"):
        store.update("Zoe", now=1.0, location="office")
    with pytest.raises(UnknownHuman, match="Zoe"):
        store.where_was("Zoe", 1.0)


def test_duplicate_registration_is_refused_and_replace_keeps_history(store, alice):
    store.register(alice)
    store.update("Alice", now=5.0, location="office", activity="work", source="perception")
    with pytest.raises(DuplicateHuman, match="already registered"):
        store.register(alice)
    with pytest.raises(DuplicateHuman, match="already registered"):
        store.register(make_human(name="ALICE", ip=""))
    with pytest.raises(DuplicateHuman, match="192.168.1.101 already belongs to 'Alice'"):
        store.register(make_human(name="Mallory"))
    older = make_human(age=35)
    store.register(older, replace=True)
    assert store.get("Alice").age == 35
    assert store.history("Alice") == [HistoryEntry(5.0, "office", "work", "perception")]


def test_register_all_is_all_or_nothing(store, alice, bob):
    store.register(bob)
    with pytest.raises(DuplicateHuman, match="Bob"):
        store.register_all([alice, bob])
    assert [h.name for h in store.humans()] == ["Bob"]
    with pytest.raises(DuplicateHuman, match="more than once"):
        store.register_all([alice, make_human(name="alice", ip="")])


def test_update_records_history_and_answers_where_was(store, alice):
    store.register(alice, now=0.0)
    store.update("Alice", now=100.0, location="office", activity="work", source="perception")
    store.update("Alice", now=200.0, location="dining_room", source="perception")
    store.update("Alice", now=300.0, activity="eat", source="verbal")
    alice_now = store.get("Alice")
    assert (alice_now.location, alice_now.activity, alice_now.last_seen) == \
        ("dining_room", "eat", 300.0)
    assert store.where_was("Alice", 150.0) == HistoryEntry(100.0, "office", "work", "perception")
    assert store.where_was("Alice", 200.0).location == "dining_room"
    assert store.where_was("Alice", 200.0).activity == "work"   # activity kept from before
    assert store.where_was("Alice", 99.0) is None
    assert [e.time for e in store.history("Alice", since=150.0)] == [200.0, 300.0]


def test_a_late_observation_enters_history_but_not_the_current_state(store, alice):
    store.register(alice)
    store.update("Alice", now=500.0, location="office", source="perception")
    store.update("Alice", now=400.0, location="alley", source="perception")
    assert store.get("Alice").location == "office"
    assert store.where_was("Alice", 450.0).location == "alley"


def test_update_colours_and_schedules(store, alice):
    store.register(alice)
    store.update("Alice", shirt_colour=[10, 20, 30] * 3)
    assert store.get("Alice").shirt_colour == ((10, 20, 30),) * 3
    entry = ScheduleEntry(0.0, 3600.0, "", "sleep")
    store.update("Alice", schedules=[entry])
    assert store.get("Alice").schedules == (entry,)
    store.update("Alice", schedules=[])
    assert store.get("Alice").schedules == ()
    assert store.history("Alice") == []        # neither is an observation


@pytest.mark.parametrize("fields, error, needle", [
    (dict(), InvalidHuman, "nothing to update"),
    (dict(shirt_colour=[1, 2, 3]), InvalidColour, "9 values"),
    (dict(shirt_colour=[0] * 8 + [300]), InvalidColour, "outside 0-255"),
    (dict(schedules=[ScheduleEntry(0.0, 7200.0, "office"), ScheduleEntry(3600.0, 9000.0, "alley")]),
     InvalidHuman, "overlap"),
    (dict(location="office", now=-1.0), InvalidHuman, "time must be"),
    (dict(location="office", now=float("nan")), InvalidHuman, "time must be"),
])
def test_bad_updates_are_refused_and_change_nothing(store, alice, fields, error, needle):
    store.register(alice)
    with pytest.raises(error, match=needle):
        store.update("Alice", **fields)
    assert store.get("Alice") == alice


def test_everything_committed_survives_reopening(tmp_path, alice):
    path = tmp_path / "humans.sqlite"
    first = HumanStore(path)
    first.register(alice)
    first.update("Alice", now=7.0, location="office", source="perception")
    first.close()
    second = HumanStore(path)
    assert second.get("Alice").location == "office"
    assert second.history("Alice")[-1].time == 7.0
    second.close()


def test_a_version_1_database_is_migrated_keeping_its_people(tmp_path):
    path = tmp_path / "v1.sqlite"
    connection = sqlite3.connect(path)
    for statement in MIGRATIONS[0]:
        connection.execute(statement)
    connection.execute(
        "INSERT INTO humans (name, ip, gender, age, r1, g1, b1, r2, g2, b2, r5, g5, b5, location,"
        " activity) VALUES ('Carol', '192.168.1.103', 'female', 68, 1, 2, 3, 4, 5, 6, 7, 8, 9, "
        "'bedroom', 'sleep')")
    connection.execute("PRAGMA user_version = 1")
    connection.commit()
    connection.close()
    store = HumanStore(path)
    carol = store.get("Carol")
    assert (carol.location, carol.last_seen, carol.shirt_colour[2]) == ("bedroom", None, (7, 8, 9))
    store.update("Carol", now=1.0, activity="read", source="perception")
    assert store.where_was("Carol", 2.0).activity == "read"
    assert store.shirts("Carol") == [(0.0, ((1, 2, 3), (4, 5, 6), (7, 8, 9)), "migrated")]
    version = sqlite3.connect(path).execute("PRAGMA user_version").fetchone()[0]
    assert version == SCHEMA_VERSION
    store.close()


def test_a_clothes_change_keeps_the_old_shirt_in_the_shirt_history(store, alice):
    store.register(alice, now=5.0)
    pyjamas = ((20, 20, 90), (22, 22, 95), (21, 21, 92))
    store.update("Alice", now=80.0, location="bedroom", source="recall", shirt_colour=pyjamas)
    assert store.get("Alice").shirt_colour == pyjamas
    times, shirts, sources = zip(*store.shirts("Alice"))
    assert times == (5.0, 80.0) and sources == ("register", "recall")
    assert shirts == (alice.shirt_colour, pyjamas)
    store.update("Alice", now=90.0, location="office", source="perception")
    assert len(store.shirts("Alice")) == 2          # an observation is not a new shirt


def _refused_untouched(path, needle):
    before = path.read_bytes()
    with pytest.raises(DatabaseUnusable, match=needle) as caught:
        HumanStore(path)
    assert str(path) in str(caught.value)
    assert path.read_bytes() == before
    return caught.value


def test_a_file_that_is_not_sqlite_is_refused_and_left_untouched(tmp_path):
    path = tmp_path / "humans.sqlite"
    path.write_bytes(b"this is not a database\n" * 100)
    _refused_untouched(path, "not an SQLite database")


def test_a_database_with_damaged_pages_is_refused_and_left_untouched(tmp_path, alice):
    path = tmp_path / "humans.sqlite"
    store = HumanStore(path)
    store.register(alice)
    store.close()
    sqlite3.connect(path).execute("PRAGMA wal_checkpoint(TRUNCATE)").close()
    data = bytearray(path.read_bytes())
    page_size = int.from_bytes(data[16:18], "big")
    data[page_size:] = b"\xde\xad\xbe\xef" * ((len(data) - page_size) // 4)   # keep the header
    path.write_bytes(bytes(data))
    _refused_untouched(path, "corrupted|unreadable")


def test_a_foreign_or_newer_database_is_refused(tmp_path):
    foreign = tmp_path / "foreign.sqlite"
    connection = sqlite3.connect(foreign)
    connection.execute("CREATE TABLE invoices (id INTEGER)")
    connection.commit()
    connection.close()
    _refused_untouched(foreign, r"holds tables \['invoices'\] but no human_db schema")
    newer = tmp_path / "newer.sqlite"
    connection = sqlite3.connect(newer)
    connection.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    connection.commit()
    connection.close()
    _refused_untouched(newer, "newer than this code")


def test_a_directory_is_refused(tmp_path):
    with pytest.raises(DatabaseUnusable, match="not a regular file"):
        HumanStore(tmp_path)


def test_two_stores_opening_a_new_file_together_both_work(tmp_path, alice, bob):
    path = tmp_path / "new.sqlite"
    stores, errors = [], []
    start = threading.Barrier(2)

    def open_store():
        start.wait()
        try:
            stores.append(HumanStore(path))
        except Exception as error:  # noqa: BLE001 - any error fails the test
            errors.append(repr(error))

    threads = [threading.Thread(target=open_store) for _ in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert errors == []
    stores[0].register(alice)
    stores[1].register(bob)
    assert [h.name for h in stores[0].humans()] == ["Alice", "Bob"]
    for store in stores:
        store.close()


def _checkpointed(tmp_path, alice):
    path = tmp_path / "humans.sqlite"
    store = HumanStore(path)
    store.register(alice)
    store.close()
    connection = sqlite3.connect(path)
    connection.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    connection.close()
    return path


@pytest.mark.parametrize("keep", [10, 100, 5000, -100])
def test_a_truncated_database_is_refused_naming_the_file(tmp_path, alice, keep):
    path = _checkpointed(tmp_path, alice)
    data = path.read_bytes()
    path.write_bytes(data[:keep])
    error = _refused_untouched(path, "truncated SQLite database")
    if keep > 100:
        assert f"({len(data[:keep])} bytes; its header states" in str(error)


def test_a_foreign_database_with_a_human_db_table_name_is_refused_untouched(tmp_path):
    foreign = tmp_path / "notes.sqlite"
    connection = sqlite3.connect(foreign)
    connection.execute("CREATE TABLE history (day TEXT, note TEXT)")
    connection.execute("CREATE TABLE tags (name TEXT)")
    connection.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
    connection.commit()
    connection.close()
    error = _refused_untouched(foreign, r"holds tables \['history', 'tags'\], which do not match "
                                        r"human_db's schema version 4")
    assert "not a human_db database" in str(error)
    connection = sqlite3.connect(foreign)
    tables = [r[0] for r in connection.execute("SELECT name FROM sqlite_master ORDER BY name")]
    connection.close()
    assert tables == ["history", "tags"]          # none of ours added


def test_an_extra_table_in_a_human_db_file_is_refused(tmp_path, alice):
    path = _checkpointed(tmp_path, alice)
    connection = sqlite3.connect(path)
    connection.execute("CREATE TABLE invoices (id INTEGER)")
    connection.commit()
    connection.close()
    _refused_untouched(path, r"differing: \['invoices'\]")


def _hold_exclusive(path):
    """A second connection in rollback-journal mode holding BEGIN EXCLUSIVE on `path`."""
    holder = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
    holder.execute("PRAGMA journal_mode = DELETE")
    holder.execute("BEGIN EXCLUSIVE")
    return holder


class SkippedPauses:
    """human_db.store's wallclock with its pauses between attempts skipped: monotonic() is the
    real clock plus every pause taken, so SQLite's own busy waits still count."""

    def __init__(self):
        self.pauses = []

    def monotonic(self):
        return time.monotonic() + sum(self.pauses)

    def sleep(self, seconds):
        self.pauses.append(seconds)

    def __getattr__(self, name):    # time(), ...: the time module's
        return getattr(time, name)


@pytest.fixture
def clock(monkeypatch):
    clock = SkippedPauses()
    monkeypatch.setattr(store_module, "wallclock", clock)
    return clock


# SQLite gives up on a lock after 0.05 s, so the store paces its attempts with its own pauses
FAST_BUSY = dict(busy_timeout=0.05)


def test_a_locked_database_is_retried_for_the_budget_then_refused(tmp_path, clock):
    path = tmp_path / "humans.sqlite"
    holder = _hold_exclusive(path)
    retries = []
    started = clock.monotonic()
    try:
        with pytest.raises(StoreBusy) as caught:
            HumanStore(path, StoreConfig(open_retry=2.5, **FAST_BUSY),
                       on_retry=lambda message: retries.append((clock.monotonic(), message)))
    finally:
        holder.execute("ROLLBACK")
        holder.close()
    assert clock.monotonic() - started >= 2.5        # the whole budget, then refused
    assert sum(clock.pauses) <= 2.5 and clock.pauses[-1] < store_module.OPEN_RETRY_PAUSE
    assert str(caught.value).startswith(f"{path}: another process holds a lock on the database "
                                        "(SQLite: database is locked) and kept it for the 2.5 s "
                                        "start-up budget (open_retry)")
    # one line per retry, paced about a pause apart (attempt starts are OPEN_RETRY_PAUSE apart;
    # each line follows SQLite's real busy wait, 0.05 s, longer on a busy machine): three when
    # those waits leave room for them in the budget, never fewer than two
    assert 2 <= len(retries) <= 3
    assert all(b[0] - a[0] > 0.5 * store_module.OPEN_RETRY_PAUSE
               for a, b in zip(retries, retries[1:]))
    assert retries[0][1].startswith(f"{path}: another process holds a lock on the database")
    assert all(f"retry {k}," in message for k, (_, message) in enumerate(retries, 1))


def test_a_lock_released_within_the_budget_lets_the_store_open(tmp_path, alice, clock):
    path = tmp_path / "humans.sqlite"
    holder = _hold_exclusive(path)
    retries = []

    def release_after_the_first_retry(message):
        retries.append(message)
        if len(retries) == 1:
            holder.execute("ROLLBACK")

    try:
        store = HumanStore(path, StoreConfig(open_retry=10.0, **FAST_BUSY),
                           on_retry=release_after_the_first_retry)
    finally:
        holder.close()
    store.register(alice)
    assert store.get("Alice").name == "Alice" and len(retries) == 1
    store.close()


@pytest.mark.parametrize("value", [-1.0, float("inf"), float("nan")])
def test_open_retry_must_be_a_finite_number_of_seconds(value):
    with pytest.raises(ValueError, match="open_retry must be a finite number of seconds >= 0"):
        StoreConfig(open_retry=value)


def test_a_person_not_met_yet_has_no_shirt_until_one_is_registered(store, alice):
    """§3.2.3: the robot stores the colours when it meets someone; before that they match
    nobody (the identification table leaves them out) and have no shirt history."""
    unmet = dataclasses.replace(alice, shirt_colour=None)
    store.register(unmet, now=1.0)
    assert store.get("Alice").shirt_colour is None
    assert store.shirt_colour_table()[0] == []
    assert store.shirts("Alice") == []
    met = ((200, 40, 40), (190, 35, 45), (185, 30, 40))
    store.update("Alice", now=30.0, location="office", source="recall", shirt_colour=met)
    assert store.get("Alice").shirt_colour == met
    names, colours = store.shirt_colour_table()
    assert names == ["Alice"] and colours[0].tolist() == [list(c) for c in met]
    assert [source for _, _, source in store.shirts("Alice")] == ["recall"]
