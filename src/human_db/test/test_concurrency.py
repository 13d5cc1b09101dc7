"""4 writer threads x 1,000 updates: no lost update, no "database is locked" reaching a caller."""
import tempfile
import threading
from pathlib import Path

import pytest
from human_factories import make_human

from human_db.store import HumanStore

WRITERS = 4
UPDATES = 1000


@pytest.fixture
def db_dir():
    """A folder in memory (tmpfs) where the machine has one: these tests are about locking and
    lost updates, which tmpfs keeps, not about fsync, whose 4,000 disk flushes took 15-19 s."""
    shm = Path("/dev/shm")
    with tempfile.TemporaryDirectory(dir=shm if shm.is_dir() else None) as folder:
        yield Path(folder)


def _hammer(stores, name_of, updates=UPDATES):
    """Run WRITERS threads, writer k doing `updates` updates through stores[k]; return errors."""
    errors = []
    start = threading.Barrier(WRITERS)

    def writer(k):
        start.wait()
        try:
            for i in range(updates):
                stores[k].update(name_of(k), now=float(i), location=f"room {k}",
                                 activity=f"step {i}", source=f"writer {k}")
        except Exception as error:  # noqa: BLE001 - any error reaching the caller fails the test
            errors.append(repr(error))

    threads = [threading.Thread(target=writer, args=(k,)) for k in range(WRITERS)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    return errors


@pytest.mark.parametrize("layout", ["one shared store", "one store per thread"])
def test_four_writers_on_one_person_lose_nothing(db_dir, layout):
    path = db_dir / "humans.sqlite"
    first = HumanStore(path)
    first.register(make_human("Alice"))
    stores = [first] * WRITERS if layout == "one shared store" else \
        [first] + [HumanStore(path) for _ in range(WRITERS - 1)]
    errors = _hammer(stores, lambda k: "Alice")
    assert errors == []
    history = first.history("Alice")
    assert len(history) == WRITERS * UPDATES
    assert {(e.source, e.activity) for e in history} == {
        (f"writer {k}", f"step {i}") for k in range(WRITERS) for i in range(UPDATES)}
    # every row is whole: the location always belongs to the writer that wrote the row
    assert all(e.location == f"room {e.source[-1]}" for e in history)
    final = first.get("Alice")
    assert final.last_seen == UPDATES - 1.0
    assert final.activity == f"step {UPDATES - 1}"
    for store in set(stores):
        store.close()


def test_four_writers_on_four_people_each_end_at_their_last_update(db_dir):
    store = HumanStore(db_dir / "humans.sqlite")
    names = ["Alice", "Bob", "Carol", "David"]
    store.register_all([make_human(n, ip=f"10.0.0.{i + 1}") for i, n in enumerate(names)])
    updates = UPDATES // 4   # the one-person test above is the 4 x 1,000 acceptance run
    assert _hammer([store] * WRITERS, lambda k: names[k], updates) == []
    for k, name in enumerate(names):
        human = store.get(name)
        assert (human.location, human.activity) == (f"room {k}", f"step {updates - 1}")
        assert len(store.history(name)) == updates
    store.close()
