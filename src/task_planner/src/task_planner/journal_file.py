"""Opening the task buffer's SQLite journal: only a journal of ours, with errors naming the file.

`open_journal` refuses, leaving the file untouched (nothing is created or converted in it):
- a file SQLite cannot read (not SQLite, truncated, damaged pages: `PRAGMA quick_check`), and
- a foreign SQLite file: one holding tables other than the journal's, or a journal table whose
  columns differ from ours (e.g. another program's database, or the human database).
The message names the file and, for a foreign file, the tables found. A missing or empty file
becomes a new journal; ':memory:' opens a journal without a file.
"""
import sqlite3
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from human_db.store import table_columns


class JournalFileError(ValueError):
    """The journal file cannot be used; the message names the file and why."""


def expected_columns(statements: Iterable[str]) -> dict[str, Any]:
    """table_columns of an in-memory database made by the journal's CREATE TABLE statements."""
    db = sqlite3.connect(":memory:")
    try:
        for statement in statements:
            db.execute(statement)
        return table_columns(db)
    finally:
        db.close()


def foreign_tables(found: Mapping[str, Any], expected: Mapping[str, Any]) -> list[str]:
    """Names of the tables in `found` that are not the journal's or differ from it, sorted."""
    return sorted(name for name, columns in found.items() if expected.get(name) != columns)


def open_journal(path: str | Path, synchronous: str, statements: Sequence[str],
                 what: str = "task buffer journal") -> sqlite3.Connection:
    """An autocommit sqlite3 connection (WAL, PRAGMA synchronous) to the journal at `path`, its
    tables made by `statements` (CREATE TABLE IF NOT EXISTS ...); JournalFileError when the file
    is unreadable or foreign (module docstring); `what` names the file's kind in messages."""
    path = str(path)
    where = f"{what} {path}"
    try:
        db = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
    except sqlite3.Error as error:
        raise JournalFileError(f"{where}: cannot open ({error})") from error
    try:
        problems = [row[0] for row in db.execute("PRAGMA quick_check")]
        if problems != ["ok"]:
            raise JournalFileError(f"{where}: corrupted ({'; '.join(problems[:3])}); refusing "
                                   "to use it, the file is left untouched")
        found, expected = table_columns(db), expected_columns(statements)
        foreign = foreign_tables(found, expected)
        if foreign:
            raise JournalFileError(
                f"{where}: not a {what}: holds tables {sorted(found)} ("
                f"{', '.join(foreign)} not as in the journal's {', '.join(sorted(expected))}); "
                "refusing to use it, the file is left untouched")
        db.execute("PRAGMA journal_mode=WAL")
        db.execute(f"PRAGMA synchronous={synchronous}")
        for statement in statements:
            db.execute(statement)
    except sqlite3.DatabaseError as error:
        db.close()
        raise JournalFileError(f"{where}: unreadable ({error}): not an SQLite file, or a "
                               "truncated or corrupted one; refusing to use it, the file is "
                               "left untouched") from error
    except JournalFileError:
        db.close()
        raise
    return db
