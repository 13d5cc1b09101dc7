"""The task buffer's journal file: an unreadable or foreign file is refused untouched, by name."""
import sqlite3

import pytest
from planner_factories import execute_sql, make_instruction

from task_planner.task_buffer import TaskBuffer, TaskBufferError


def _tables(path):
    db = sqlite3.connect(path)
    try:
        return [row[0] for row in db.execute("SELECT name FROM sqlite_master WHERE type = 'table' "
                                             "ORDER BY name")]
    finally:
        db.close()


def _refused_untouched(path, pattern):
    before = path.read_bytes()
    with pytest.raises(TaskBufferError, match=pattern) as caught:
        TaskBuffer(path)
    assert str(caught.value).startswith(f"task buffer journal {path}: ")
    assert path.read_bytes() == before
    assert sorted(p.name for p in path.parent.iterdir()) == [path.name]   # no -wal, no -shm
    return str(caught.value)


def _journal(tmp_path):
    path = tmp_path / "buffer.sqlite"
    buffer = TaskBuffer(path)
    for i in range(1, 40):
        buffer.submit(make_instruction(i, 2, text="bring the remote " * 20), now=1.0)
    buffer._db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    buffer._db.close()
    for suffix in ("-wal", "-shm"):
        (tmp_path / f"buffer.sqlite{suffix}").unlink(missing_ok=True)
    return path


def test_another_programs_sqlite_file_is_refused_naming_its_tables(tmp_path):
    path = tmp_path / "humans.sqlite"
    execute_sql(path, "CREATE TABLE humans (id INTEGER PRIMARY KEY, name TEXT)",
                "CREATE TABLE history (id INTEGER PRIMARY KEY, time REAL)")
    message = _refused_untouched(path, r"not a task buffer journal: holds tables "
                                       r"\['history', 'humans'\] \(history, humans not as in the "
                                       r"journal's instructions, robot_state, searches\)")
    assert message.endswith("refusing to use it, the file is left untouched")
    assert _tables(path) == ["history", "humans"]          # none of the journal's tables added


def test_a_foreign_instructions_table_is_refused(tmp_path):
    path = tmp_path / "todo.sqlite"
    execute_sql(path, "CREATE TABLE instructions (id INTEGER PRIMARY KEY, what TEXT)")
    _refused_untouched(path, r"holds tables \['instructions'\] \(instructions not as in")


def test_a_file_that_is_not_sqlite_is_refused_by_name(tmp_path):
    path = tmp_path / "buffer.sqlite"
    path.write_bytes(b"instructions, one per line\n" * 100)
    _refused_untouched(path, r"unreadable \(file is not a database\): not an SQLite file, or a "
                             r"truncated or corrupted one")


@pytest.mark.parametrize("keep", [50, 5000, -1000])
def test_a_truncated_journal_is_refused_by_name(tmp_path, keep):
    path = _journal(tmp_path)
    path.write_bytes(path.read_bytes()[:keep])
    _refused_untouched(path, r"unreadable \(.*\)|corrupted \(")


def test_our_journal_reopens_and_an_older_one_without_searches_is_accepted(tmp_path):
    path = _journal(tmp_path)
    assert len(TaskBuffer(path).records()) == 39
    execute_sql(path, "DROP TABLE searches")
    assert len(TaskBuffer(path).records()) == 39
    assert _tables(path) == ["instructions", "robot_state", "searches"]
    empty = tmp_path / "empty.sqlite"
    empty.write_bytes(b"")
    assert TaskBuffer(empty).records() == [] and TaskBuffer(":memory:").records() == []


def test_a_corrupt_row_is_quarantined_naming_the_row(tmp_path):
    path = _journal(tmp_path)
    execute_sql(path, "UPDATE instructions SET gamma = -5 WHERE id = 3")
    buffer = TaskBuffer(path)
    assert [i for i, _ in buffer.quarantined] == [3]
    assert buffer.quarantined[0][1].startswith("quarantined: journal row 3 is no valid "
                                               "instruction: instruction 3: gamma")
    assert 3 not in {r.instruction.id for r in buffer.records()}
