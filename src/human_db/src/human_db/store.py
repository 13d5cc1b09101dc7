"""The household store (thesis 000 §3.4): SQLite in WAL mode with schema migrations, a history of
observations, and safe concurrent use (one connection per working thread, busy timeout + retry).

A person's row that does not load (SQLite keeps any value in any column: a BLOB or number for a
text, text for a time, a schedule entry of the wrong kind; written by hand or damaged) is left
out of `humans` and the shirt table, with the reason in `quarantined`; `get` refuses it with the
reason. The other people are served as usual.
"""
import math
import os
import sqlite3
import threading
import time as wallclock
from collections.abc import Callable, Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, TypeVar

import numpy as np
import numpy.typing as npt

from human_db.errors import (DatabaseUnusable, DuplicateHuman, InvalidHuman, StoreBusy,
                             UnknownHuman)
from human_db.colour import shirt_colours
from human_db.model import Human, ScheduleEntry, check_ip, check_schedules
from human_db.schema import COLOUR_COLUMNS, MIGRATIONS, SCHEMA_VERSION

SQLITE_HEADER = b"SQLite format 3\x00"
SQLITE_HEADER_SIZE = 100     # [bytes] the database header on page 1
OPEN_RETRY_PAUSE = 1.0       # [s] at start, one attempt per this long while the file is locked
SQLITE_BUSY, SQLITE_LOCKED = 5, 6
SYNCHRONOUS_LEVELS = ("OFF", "NORMAL", "FULL", "EXTRA")
_HUMAN_COLUMNS = ("id", "name", "ip", "gender", "age") + COLOUR_COLUMNS + (
    "location", "activity", "last_seen", "shirt_known")
T = TypeVar("T")
Schema = dict[str, tuple[tuple[str, str, int, int], ...]]   # table -> (column, type, notnull, pk)


@dataclass(frozen=True)
class StoreConfig:
    busy_timeout: float = 5.0     # [s] SQLite waits this long for a lock before reporting busy
    retry_timeout: float = 30.0   # [s] an operation retries a busy database for this long in all
    synchronous: str = "FULL"     # SQLite fsync level: FULL also survives power loss
    open_retry: float = 10.0      # [s] at start, a database locked by another process is
                                  # retried this long (0 = one attempt)

    def __post_init__(self) -> None:
        if self.synchronous not in SYNCHRONOUS_LEVELS:
            raise ValueError(f"synchronous must be one of {SYNCHRONOUS_LEVELS}, "
                             f"got {self.synchronous!r}")
        if not (self.busy_timeout > 0 and self.retry_timeout > 0):
            raise ValueError("busy_timeout and retry_timeout must be > 0 s")
        if not (0 <= self.open_retry < math.inf):
            raise ValueError(f"open_retry must be a finite number of seconds >= 0, "
                             f"got {self.open_retry!r}")


@dataclass(frozen=True)
class HistoryEntry:
    """One row of a person's history: where they were and what they did at `time`."""

    time: float       # [s]
    location: str
    activity: str
    source: str       # who recorded it: "perception", "verbal", "register", ...


class HumanStore:
    """Every household member, their schedules and history, in one SQLite file."""

    def __init__(self, path: str | os.PathLike[str], config: StoreConfig = StoreConfig(),
                 on_retry: Callable[[str], None] | None = None) -> None:
        """Open (or create) the database at `path`. A file that is not a usable human database
        raises DatabaseUnusable naming it; one locked by another process is retried for
        config.open_retry seconds, calling on_retry(message) before each retry, then raises
        StoreBusy."""
        self.path = os.path.abspath(path)
        self.config = config
        self._on_retry = on_retry
        self.busy_retries = 0          # how often an operation found the database locked
        self._revision = 0             # bumped by every committed write of this process
        self._lock = threading.Lock()  # guards the pool and the counters
        # idle connections; a working thread takes its own
        self._pool: list[sqlite3.Connection] = []
        self._connections: list[sqlite3.Connection] = []   # every connection, to close them all
        # humans row id -> why it does not load (last `humans`)
        self._quarantined: dict[int, str] = {}
        check_database_file(self.path)
        self._open()

    def _open(self) -> None:
        """Check and migrate the schema; retry a locked file for config.open_retry seconds."""
        budget = self.config.open_retry
        deadline = wallclock.monotonic() + budget
        attempt = 0
        while True:
            attempt += 1
            started = wallclock.monotonic()
            try:
                self._open_once()
                return
            except sqlite3.OperationalError as error:   # only "locked" / "busy" arrive here
                left = deadline - wallclock.monotonic()
                if left <= 0:
                    raise StoreBusy(
                        f"{self.path}: another process holds a lock on the database (SQLite: "
                        f"{error}) and kept it for the {budget:g} s start-up budget "
                        "(open_retry); stop that process or let it finish, then start "
                        "again") from error
                if self._on_retry is not None:
                    self._on_retry(f"{self.path}: another process holds a lock on the "
                                   f"database (SQLite: {error}); retry {attempt}, "
                                   f"{left:.1f} s of the {budget:g} s start-up budget left")
                # SQLite's busy handler has waited already; pace fast failures to the pause
                waited = wallclock.monotonic() - started
                wallclock.sleep(max(0.0, min(OPEN_RETRY_PAUSE - waited, left)))

    def _open_once(self) -> None:
        """One attempt at opening: a busy error is raised as sqlite3.OperationalError, any
        other SQLite error as DatabaseUnusable naming the file."""
        os.makedirs(os.path.dirname(self.path), exist_ok=True)
        connection = sqlite3.connect(self.path, isolation_level=None,
                                     timeout=min(self.config.busy_timeout, OPEN_RETRY_PAUSE))
        try:
            connection.execute("PRAGMA foreign_keys = ON")
            open_schema(connection, self.path)
        except sqlite3.DatabaseError as error:
            if is_busy(error):
                raise
            raise DatabaseUnusable(unreadable_message(self.path, error)) from error
        finally:
            if connection.in_transaction:
                connection.execute("ROLLBACK")
            connection.close()

    # -- connections and transactions -------------------------------------------------------
    def _connect(self) -> sqlite3.Connection:
        os.makedirs(os.path.dirname(self.path), exist_ok=True)
        connection = sqlite3.connect(self.path, timeout=self.config.busy_timeout,
                                     isolation_level=None, check_same_thread=False)
        connection.execute(f"PRAGMA busy_timeout = {int(self.config.busy_timeout * 1000)}")
        connection.execute("PRAGMA foreign_keys = ON")
        connection.execute(f"PRAGMA synchronous = {self.config.synchronous}")
        with self._lock:
            self._connections.append(connection)
        return connection

    @contextmanager
    def _connection(self) -> Iterator[sqlite3.Connection]:
        with self._lock:
            connection = self._pool.pop() if self._pool else None
        if connection is None:
            connection = self._connect()
        try:
            yield connection
        finally:
            if connection.in_transaction:
                connection.execute("ROLLBACK")
            with self._lock:
                self._pool.append(connection)

    def _retrying(self, attempt: Callable[[], T]) -> T:
        deadline = wallclock.monotonic() + self.config.retry_timeout
        pause = 0.001  # [s] first back-off; doubles up to 0.1 s
        while True:
            try:
                return attempt()
            except sqlite3.OperationalError as error:
                if not is_busy(error):
                    raise
                if wallclock.monotonic() >= deadline:
                    raise StoreBusy(f"{self.path}: database stayed locked for "
                                    f"{self.config.retry_timeout:.0f} s ({error})") from error
                with self._lock:
                    self.busy_retries += 1
                wallclock.sleep(pause)
                pause = min(2 * pause, 0.1)

    def _transaction(self, work: Callable[[sqlite3.Connection], T], write: bool) -> T:
        def attempt() -> T:
            with self._connection() as connection:
                connection.execute("BEGIN IMMEDIATE" if write else "BEGIN")
                result = work(connection)
                connection.execute("COMMIT")
                return result
        result = self._retrying(attempt)
        if write:
            with self._lock:
                self._revision += 1
        return result

    @property
    def quarantined(self) -> dict[int, str]:
        """{humans row id: reason} of the rows the last `humans` left out: they do not load."""
        with self._lock:
            return dict(self._quarantined)

    @property
    def revision(self) -> int:
        """A number that changes whenever this process commits a write."""
        with self._lock:
            return self._revision

    def close(self) -> None:
        with self._lock:
            for connection in self._connections:
                connection.close()
            self._connections.clear()
            self._pool.clear()

    # -- writes -------------------------------------------------------------------------------
    def register(self, human: Human, replace: bool = False, now: float | None = None) -> None:
        """Initialization (§3.2.3): add a person; a repeated name or phone IP is refused unless
        `replace`, which keeps the person's history. A given location/activity enters the history
        at `now` [s] (default: wall-clock time) with source "register"."""
        self.register_all([human], replace, now)

    def initialize(self, name: str, query_colours: tuple, gender: str, age: int, ip: str = "",
                   now: float | None = None) -> Human:
        """§3.2.3 Initialization phase: register a newly met person (name, gender and age asked
        by the robot) with the shirt colours at joints 1, 2, 5 of the query observation."""
        human = Human(name=name, gender=gender, age=age, ip=ip, shirt_colour=query_colours)
        self.register(human, now=now)
        return human

    def register_all(self, humans: Sequence[Human], replace: bool = False,
                     now: float | None = None) -> None:
        """Register several people in one transaction: all of them, or none on any error."""
        now = _check_time(wallclock.time() if now is None else now)
        names = [human.name.lower() for human in humans]
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise DuplicateHuman(f"names given more than once: {repeated}")

        def work(connection: sqlite3.Connection) -> None:
            for human in humans:
                _register(connection, human, replace, now)
        self._transaction(work, write=True)

    def update(self, name: str, now: float | None = None, location: str = "",
               activity: str = "", source: str = "", shirt_colour: Any = None,
               schedules: Iterable[ScheduleEntry] | None = None) -> Human:
        """Record an observation and/or replace colours or schedules, in one transaction.

        A non-empty `location` or `activity` (the other one is kept) enters the history at `now`
        [s] and becomes the current state unless an observation newer than `now` is already there.
        Returns the updated Human."""
        now = _check_time(wallclock.time() if now is None else now)
        observed = bool(location or activity)
        if not (observed or shirt_colour is not None or schedules is not None):
            raise InvalidHuman(f"update of {name!r}: nothing to update (no location, activity, "
                               "shirt colour or schedules)")
        colours = None if shirt_colour is None else \
            shirt_colours(shirt_colour, f"update of {name!r}: shirt colour")
        entries = None if schedules is None else \
            check_schedules(schedules, f"update of {name!r}: schedules")

        def work(connection: sqlite3.Connection) -> Human:
            human_id, current_location, current_activity, last_seen = _row_or_raise(
                connection, "SELECT id, location, activity, last_seen FROM humans WHERE name = ?",
                name)
            if colours is not None:
                assignments = ", ".join(f"{c} = ?" for c in COLOUR_COLUMNS)
                connection.execute(f"UPDATE humans SET {assignments}, shirt_known = 1 "
                                   "WHERE id = ?",
                                   tuple(int(c) for c in colours.ravel()) + (human_id,))
                _record_shirt(connection, human_id, now, colours, source or "update")
            if entries is not None:
                _replace_schedules(connection, human_id, entries)
            if observed:
                new_location = location or current_location
                new_activity = activity or current_activity
                connection.execute(
                    "INSERT INTO history (human_id, time, location, activity, source) "
                    "VALUES (?, ?, ?, ?, ?)", (human_id, now, new_location, new_activity, source))
                if last_seen is None or now >= last_seen:
                    connection.execute(
                        "UPDATE humans SET location = ?, activity = ?, last_seen = ? "
                        "WHERE id = ?", (new_location, new_activity, now, human_id))
            return _load_human(connection, "name = ?", name)
        return self._transaction(work, write=True)

    # -- reads --------------------------------------------------------------------------------
    def get(self, name: str) -> Human:
        """The person named `name` (case-insensitive); raises UnknownHuman."""
        return self._transaction(lambda c: _load_human(c, "name = ?", name), write=False)

    def get_by_ip(self, ip: str) -> Human:
        """The person whose phone has IP `ip`; raises UnknownHuman (or InvalidHuman: not an IP)."""
        ip = check_ip(ip, "phone IP")
        if not ip:
            raise InvalidHuman("phone IP: empty")
        return self._transaction(lambda c: _load_human(c, "ip = ?", ip), write=False)

    def humans(self) -> list[Human]:
        """Every household member whose row loads, ordered by name; the others are left out
        and kept in `quarantined` with the reason."""
        def work(connection: sqlite3.Connection) -> tuple[list[Human], dict[int, str]]:
            rows = connection.execute(f"SELECT {', '.join(_HUMAN_COLUMNS)} FROM humans "
                                      "ORDER BY name").fetchall()
            schedules: dict[int, list[tuple[Any, ...]]] = {}
            for row in connection.execute("SELECT human_id, rowid, start_s, end_s, place, "
                                          "activity FROM schedules"):
                schedules.setdefault(row[0], []).append(row[1:])
            humans: list[Human] = []
            quarantined: dict[int, str] = {}
            for row in rows:
                try:
                    humans.append(_human_from_row(row, schedules.get(row[0], ())))
                except InvalidHuman as error:
                    quarantined[row[0]] = f"quarantined: {self.path}: {error}"
            return humans, quarantined
        humans, quarantined = self._transaction(work, write=False)
        with self._lock:
            self._quarantined = quarantined
        return humans

    def count(self) -> int:
        return self._transaction(
            lambda c: c.execute("SELECT COUNT(*) FROM humans").fetchone()[0], write=False)

    def shirt_colour_table(self) -> tuple[list[str], npt.NDArray[np.int64]]:
        """(names, (M, 3, 3) int array) of every person the robot has met (a shirt registered)
        whose row loads, ordered by name: the input of identification."""
        met = [human for human in self.humans() if human.shirt_colour is not None]
        colours = np.array([h.shirt_colour for h in met], dtype=np.int64).reshape(len(met), 3, 3)
        return [human.name for human in met], colours

    def history(self, name: str, since: float = -math.inf,
                until: float = math.inf) -> list[HistoryEntry]:
        """The person's history with since <= time <= until [s], oldest first."""
        def work(connection: sqlite3.Connection) -> list[HistoryEntry]:
            human_id = _row_or_raise(connection, "SELECT id FROM humans WHERE name = ?", name)[0]
            rows = connection.execute(
                "SELECT time, location, activity, source FROM history WHERE human_id = ? "
                "AND time >= ? AND time <= ? ORDER BY time, id", (human_id, since, until))
            return [HistoryEntry(*row) for row in rows]
        return self._transaction(work, write=False)

    def shirts(self, name: str) -> list[tuple[float, tuple[tuple[int, ...], ...], str]]:
        """Every shirt `name` has been registered in, oldest first: [(time [s], ((r, g, b) x 3),
        source)] (source "register", "migrated", or the updater's, e.g. "recall")."""
        def work(connection: sqlite3.Connection
                 ) -> list[tuple[float, tuple[tuple[int, ...], ...], str]]:
            human_id = _row_or_raise(connection, "SELECT id FROM humans WHERE name = ?", name)[0]
            rows = connection.execute(
                f"SELECT time, {', '.join(COLOUR_COLUMNS)}, source FROM shirts "
                "WHERE human_id = ? ORDER BY time, id", (human_id,)).fetchall()
            return [(r[0], (tuple(r[1:4]), tuple(r[4:7]), tuple(r[7:10])), r[10]) for r in rows]
        return self._transaction(work, write=False)

    def where_was(self, name: str, when: float) -> HistoryEntry | None:
        """The last history entry at or before `when` [s] ("where was Bob at 10:00"), or None."""
        def work(connection: sqlite3.Connection) -> HistoryEntry | None:
            human_id = _row_or_raise(connection, "SELECT id FROM humans WHERE name = ?", name)[0]
            row = connection.execute(
                "SELECT time, location, activity, source FROM history WHERE human_id = ? "
                "AND time <= ? ORDER BY time DESC, id DESC LIMIT 1", (human_id, when)).fetchone()
            return None if row is None else HistoryEntry(*row)
        return self._transaction(work, write=False)


def is_busy(error: sqlite3.Error) -> bool:
    """True when an sqlite3 error means "database is locked/busy" (worth retrying)."""
    code = getattr(error, "sqlite_errorcode", None)
    if code is not None:
        return code & 0xFF in (SQLITE_BUSY, SQLITE_LOCKED)
    return "locked" in str(error) or "busy" in str(error)


def check_database_file(path: str) -> None:
    """Refuse (DatabaseUnusable, naming the file) anything but a missing, empty or SQLite file,
    and an SQLite file shorter than its header says (truncated)."""
    if not os.path.exists(path):
        return
    if not os.path.isfile(path):
        raise DatabaseUnusable(f"{path}: not a regular file; refusing to use it")
    with open(path, "rb") as stream:
        header = stream.read(SQLITE_HEADER_SIZE)
    if not header:
        return
    if len(header) < SQLITE_HEADER_SIZE and SQLITE_HEADER.startswith(header[:16]):
        raise DatabaseUnusable(f"{path}: truncated SQLite database ({len(header)} bytes, less "
                               f"than its {SQLITE_HEADER_SIZE}-byte header); refusing to start, "
                               "the file is left untouched")
    if header[:16] != SQLITE_HEADER:
        raise DatabaseUnusable(f"{path}: not an SQLite database (corrupted header "
                               f"{header[:16]!r}); refusing to start, the file is left untouched")
    truncation = truncation_note(path, header)
    if truncation:
        raise DatabaseUnusable(f"{path}: {truncation}; refusing to start, the file is left "
                               "untouched")


def truncation_note(path: str, header: bytes) -> str:
    """"truncated SQLite database (...)" when the file is shorter than the page count its header
    states, else "". The header's count is trusted only when valid (its version-valid-for
    number equals the change counter) and no write-ahead log holds pages not yet written
    back (a checkpoint may be under way)."""
    page_size = int.from_bytes(header[16:18], "big")
    page_size = 65536 if page_size == 1 else page_size
    pages = int.from_bytes(header[28:32], "big")
    valid = header[24:28] == header[92:96] and pages > 0
    wal = f"{path}-wal"
    if not valid or (os.path.exists(wal) and os.path.getsize(wal) > 0):
        return ""
    size, expected = os.path.getsize(path), pages * page_size
    if size >= expected:
        return ""
    return (f"truncated SQLite database ({size} bytes; its header states {pages} pages of "
            f"{page_size} bytes = {expected} bytes)")


def unreadable_message(path: str, error: sqlite3.Error) -> str:
    """The DatabaseUnusable message for an SQLite error other than "locked"."""
    return (f"{path}: unreadable database ({error}): the file is corrupted or truncated; "
            "refusing to start, the file is left untouched")


def reference_schema(version: int) -> Schema:
    """{table: ((column, type, notnull, pk), ...)} of the human_db schema at `version`, built by
    running MIGRATIONS[:version] on an in-memory database."""
    connection = sqlite3.connect(":memory:")
    try:
        for statements in MIGRATIONS[:version]:
            for statement in statements:
                connection.execute(statement)
        return table_columns(connection)
    finally:
        connection.close()


def table_columns(connection: sqlite3.Connection) -> Schema:
    """{table: ((column, type, notnull, pk), ...)} of every table but SQLite's own."""
    names = [row[0] for row in connection.execute(
        "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%' "
        "ORDER BY name")]
    return {name: tuple((row[1], row[2].upper(), row[3], row[5]) for row in
                        connection.execute("SELECT * FROM pragma_table_info(?)", (name,)))
            for name in names}


def open_schema(connection: sqlite3.Connection, path: str) -> None:
    """Check integrity and the schema, switch to WAL, migrate to SCHEMA_VERSION.

    Raises DatabaseUnusable naming the file when it is corrupted, newer than this code or not
    human_db's (tables other than those of its schema version, or columns that differ): such a
    file is never written to. An SQLite "locked" error is raised as it is (the caller retries).
    The checks read one snapshot (one read transaction): another process may be migrating."""
    try:
        connection.execute("BEGIN")
        problems = [row[0] for row in connection.execute("PRAGMA quick_check")]
        if problems != ["ok"]:
            raise DatabaseUnusable(f"{path}: database is corrupted ({'; '.join(problems[:3])}); "
                                   "refusing to start, the file is left untouched")
        version = connection.execute("PRAGMA user_version").fetchone()[0]
        found = table_columns(connection)
        connection.execute("COMMIT")
    except sqlite3.DatabaseError as error:
        if is_busy(error):
            raise
        raise DatabaseUnusable(unreadable_message(path, error)) from error
    tables = sorted(found)
    if version > SCHEMA_VERSION:
        raise DatabaseUnusable(f"{path}: schema version {version} is newer than this code's "
                               f"{SCHEMA_VERSION}; refusing to use it")
    if version == 0 and tables:
        raise DatabaseUnusable(f"{path}: holds tables {tables} but no human_db schema; "
                               "refusing to use it, the file is left untouched")
    if version > 0:
        expected = reference_schema(version)
        if found != expected:
            differ = sorted(t for t in set(found) | set(expected)
                            if found.get(t) != expected.get(t))
            raise DatabaseUnusable(
                f"{path}: holds tables {tables}, which do not match human_db's schema version "
                f"{version} (tables {sorted(expected)}; differing: {differ}); not a human_db "
                "database, refusing to use it, the file is left untouched")
    connection.execute("PRAGMA journal_mode = WAL")
    migrate(connection, version)


def migrate(connection: sqlite3.Connection, version: int) -> None:
    """Apply MIGRATIONS[version:] one transaction each, bumping PRAGMA user_version."""
    for target in range(version + 1, SCHEMA_VERSION + 1):
        connection.execute("BEGIN IMMEDIATE")
        try:
            if connection.execute("PRAGMA user_version").fetchone()[0] >= target:
                connection.execute("ROLLBACK")   # another process migrated meanwhile
                continue
            for statement in MIGRATIONS[target - 1]:
                connection.execute(statement)
            connection.execute(f"PRAGMA user_version = {target}")
            connection.execute("COMMIT")
        except BaseException:
            connection.execute("ROLLBACK")
            raise


def _check_time(now: object) -> float:
    if not isinstance(now, int | float) or not math.isfinite(now) or now < 0:
        raise InvalidHuman(f"time must be a finite number of seconds >= 0, got {now!r}")
    return float(now)


def _register(connection: sqlite3.Connection, human: Human, replace: bool, now: float) -> None:
    row = connection.execute("SELECT id, name FROM humans WHERE name = ?",
                             (human.name,)).fetchone()
    if row is not None and not replace:
        raise DuplicateHuman(f"{human.name!r} is already registered (as {row[1]!r}); "
                             "register with replace to overwrite the record")
    _refuse_shared_ip(connection, human.ip, human.name)
    values = _human_values(human)
    if row is None:
        inserted = connection.execute(
            f"INSERT INTO humans ({', '.join(_HUMAN_COLUMNS[1:])}) VALUES "
            f"({', '.join('?' * len(values))})", values).lastrowid
        if inserted is None:   # sqlite3 sets it after every successful INSERT
            raise DatabaseUnusable(f"registering {human.name!r}: SQLite returned no row id")
        human_id = inserted
    else:
        human_id = row[0]
        assignments = ", ".join(f"{c} = ?" for c in _HUMAN_COLUMNS[1:])
        connection.execute(f"UPDATE humans SET {assignments} WHERE id = ?", values + (human_id,))
    _replace_schedules(connection, human_id, human.schedules)
    if human.shirt_colour is not None:
        _record_shirt(connection, human_id, now, human.shirt_colour, "register")
    if human.location or human.activity:
        connection.execute("INSERT INTO history (human_id, time, location, activity, source) "
                           "VALUES (?, ?, ?, ?, 'register')",
                           (human_id, now, human.location, human.activity))


def _record_shirt(connection: sqlite3.Connection, human_id: int, now: float,
                  colours: Iterable[Iterable[float]], source: str) -> None:
    """Add a shirt to the person's shirt history (schema v3)."""
    values = tuple(int(c) for joint in colours for c in joint)
    connection.execute(f"INSERT INTO shirts (human_id, time, {', '.join(COLOUR_COLUMNS)}, source) "
                       f"VALUES (?, ?, {', '.join('?' * len(values))}, ?)",
                       (human_id, now) + values + (source,))


def _refuse_shared_ip(connection: sqlite3.Connection, ip: str, name: str) -> None:
    if not ip:
        return
    other = connection.execute("SELECT name FROM humans WHERE ip = ? AND name != ?",
                               (ip, name)).fetchone()
    if other is not None:
        raise DuplicateHuman(f"phone IP {ip} already belongs to {other[0]!r}")


def _human_values(human: Human) -> tuple[Any, ...]:
    shirt = human.shirt_colour
    known = shirt is not None
    colours = tuple(channel for joint in shirt for channel in joint) if shirt is not None \
        else (0,) * len(COLOUR_COLUMNS)
    return (human.name, human.ip, human.gender, human.age) + colours + (
        human.location, human.activity, human.last_seen, int(known))


def _replace_schedules(connection: sqlite3.Connection, human_id: int,
                       entries: Iterable[ScheduleEntry]) -> None:
    connection.execute("DELETE FROM schedules WHERE human_id = ?", (human_id,))
    connection.executemany(
        "INSERT INTO schedules (human_id, start_s, end_s, place, activity) VALUES (?, ?, ?, ?, ?)",
        [(human_id, e.start, e.end, e.place, e.activity) for e in entries])


def _row_or_raise(connection: sqlite3.Connection, query: str, name: str) -> tuple[Any, ...]:
    row = connection.execute(query, (name,)).fetchone()
    if row is None:
        raise UnknownHuman(f"no household member named {name!r}")
    return row


def _load_human(connection: sqlite3.Connection, where: str, key: str) -> Human:
    row = connection.execute(f"SELECT {', '.join(_HUMAN_COLUMNS)} FROM humans WHERE {where}",
                             (key,)).fetchone()
    if row is None:
        what = "has phone IP" if where.startswith("ip") else "named"
        raise UnknownHuman(f"no household member {what} {key!r}")
    schedules = connection.execute("SELECT rowid, start_s, end_s, place, activity FROM schedules "
                                   "WHERE human_id = ?", (row[0],)).fetchall()
    return _human_from_row(row, schedules)


def _human_from_row(row: Sequence[Any], schedules: Iterable[Sequence[Any]]) -> Human:
    """The Human of a humans row and its schedules rows (rowid, start_s, end_s, place,
    activity); InvalidHuman naming the row and why when it does not load."""
    values = dict(zip(_HUMAN_COLUMNS, row))
    try:
        problem = _column_problem(values)
        if problem:
            raise InvalidHuman(problem)
        colours = [values[c] for c in COLOUR_COLUMNS]
        shirt = (colours[0:3], colours[3:6], colours[6:9]) if values["shirt_known"] else None
        return Human(name=values["name"], ip=values["ip"], gender=values["gender"],
                     age=values["age"], shirt_colour=shirt,
                     location=values["location"], activity=values["activity"],
                     schedules=tuple(_schedule_entry(r) for r in schedules),
                     last_seen=values["last_seen"])
    except InvalidHuman as error:
        raise InvalidHuman(f"humans row {values['id']} ({values['name']!r:.40}) does not load: "
                           f"{error}") from None


_TEXT_COLUMNS = ("name", "ip", "gender", "location", "activity")


def _column_problem(values: Mapping[str, Any]) -> str:
    """What a humans row holds that its columns' kinds do not allow (SQLite stores any value
    in any column), or ""."""
    for name in _TEXT_COLUMNS:
        if not isinstance(values[name], str):
            return f"column {name} holds {values[name]!r:.40}, not text"
    seen = values["last_seen"]
    if seen is not None and not (isinstance(seen, int | float) and math.isfinite(seen)):
        return f"column last_seen holds {seen!r:.40}, not a time"
    return ""


def _schedule_entry(row: Sequence[Any]) -> ScheduleEntry:
    """The ScheduleEntry of a schedules row (rowid, start_s, end_s, place, activity)."""
    rowid, start, end, place, activity = row
    for name, value, kind in (("start_s", start, int | float), ("end_s", end, int | float),
                              ("place", place, str), ("activity", activity, str)):
        if not isinstance(value, kind):
            raise InvalidHuman(f"schedules row {rowid}: column {name} holds {value!r:.40}, "
                               f"not {'text' if kind is str else 'a number'}")
    return ScheduleEntry(start, end, place, activity)
