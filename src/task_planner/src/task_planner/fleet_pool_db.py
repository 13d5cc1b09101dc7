"""The fleet pool's database, ROS-free: an SQLite file on one host or a PostgreSQL server for
several, chosen by where the pool is (`open_pool_db`):
- a path, `:memory:` or `sqlite:///abs/path`: an SQLite file (WAL; processes of one host: WAL
  needs shared memory, so never on a network file system). `BEGIN IMMEDIATE` takes the one
  write lock at the start of every write transaction, so writes never interleave;
- `postgresql://[user[:password]@]host[:port]/database`: a PostgreSQL server (Debian's
  postgresql 15, python3-psycopg2). Writes lock rows (a claim: `SELECT ... FOR UPDATE SKIP
  LOCKED`); the writes that read a counter or a holder before they insert (`serialize`: share,
  next_id, enter) first lock the small `pool_ids` table, so shared instructions get their
  sequence numbers in commit order and nobody misses one. A lost connection (server restart, cut
  network; noticed within about 10 s by TCP keepalives) raises PoolUnavailable naming the
  server, and the next call connects again, never inside a transaction (it was rolled back: a
  transaction's writes land all or none). A connection attempt that failed after t seconds (an
  unreachable host: up to 2 s) is not tried again for 2 t, so a robot whose network is cut spends
  at most a third of its time waiting for the server. A session stuck inside a transaction longer
  than 10 s is ended by the server, so a robot whose network was cut never keeps rows locked.
Both run the same SQL, written with `?` placeholders.
"""
import re
import sqlite3
import time
from collections.abc import Iterator, Sequence
from typing import Any, Protocol

from task_planner.journal_file import JournalFileError, expected_columns, open_journal

BUSY_TIMEOUT_MS = 10000   # how long a write waits for another robot's transaction
_SQLITE_PREFIX, _PG_PREFIXES = "sqlite://", ("postgresql://", "postgres://")
# the server ends a robot's session this long inside one transaction (its connection was cut)
_PG_OPTIONS = (f"-c lock_timeout={BUSY_TIMEOUT_MS} "
               f"-c idle_in_transaction_session_timeout={BUSY_TIMEOUT_MS}")
_PG_CONNECT = dict(connect_timeout=2, keepalives=1, keepalives_idle=5, keepalives_interval=2,
                   keepalives_count=3, tcp_user_timeout=BUSY_TIMEOUT_MS, options=_PG_OPTIONS,
                   application_name="fleet_pool")
_PASSWORD = re.compile(r"://([^:@/]*):[^@/]*@")
_SCHEMA_LOCK = 0x666C656574   # advisory lock: robots starting together make the tables once


def without_password(url: str) -> str:
    """The URL to show: its password, if any, replaced by ***."""
    return _PASSWORD.sub(r"://\1:***@", url)


class FleetPoolError(ValueError):
    """The pool's file or server, or a request to it, is unusable; the message names it."""


class PoolUnavailable(FleetPoolError):
    """The pool's server cannot be reached now (or is busy past the lock timeout); the next call
    connects again."""


class Rows(Protocol):
    """What a pool database's `run` returns: a DB-API cursor over the statement's rows."""

    @property
    def rowcount(self) -> int: ...

    def fetchone(self) -> Any: ...

    def fetchall(self) -> list[Any]: ...

    def __iter__(self) -> Iterator[Any]: ...


def open_pool_db(where: object, tables: Sequence[str],
                 synchronous: str = "FULL") -> "SQLitePool | PostgreSQLPool":
    """The database of the pool at `where` (module docstring), its `tables` made (CREATE TABLE
    IF NOT EXISTS ..., SQLite types); FleetPoolError when it is foreign or unusable."""
    where = str(where)
    if where.startswith(_PG_PREFIXES):
        return PostgreSQLPool(where, tables)
    if where.startswith(_SQLITE_PREFIX):
        if not where.startswith(_SQLITE_PREFIX + "/"):
            raise FleetPoolError(f"fleet pool {where}: an SQLite URL names an absolute path "
                                 "(sqlite:///abs/path)")
        where = where[len(_SQLITE_PREFIX):]
    elif re.match(r"^[a-z][a-z0-9+.-]*://", where):
        raise FleetPoolError(f"fleet pool {where}: unknown kind of database (a path, "
                             "sqlite:///abs/path or postgresql://host/database)")
    return SQLitePool(where, tables, synchronous)


class SQLitePool:
    """The pool in one SQLite file (`name`: its path)."""

    row_lock = ""   # BEGIN IMMEDIATE holds the whole file

    def __init__(self, path: str, tables: Sequence[str], synchronous: str) -> None:
        try:
            self.db = open_journal(path, synchronous, tables, "fleet pool")
        except JournalFileError as error:
            raise FleetPoolError(str(error)) from error
        self.db.execute(f"PRAGMA busy_timeout={BUSY_TIMEOUT_MS}")
        self.name = path

    @staticmethod
    def is_integer(column: str) -> str:
        """An SQL condition: `column` holds an integer (SQLite keeps any value in any column)."""
        return f"typeof({column}) = 'integer'"

    def run(self, sql: str, args: Sequence[object] = ()) -> sqlite3.Cursor:
        return self.db.execute(sql, args)

    def serialize(self) -> None:
        """Writes are serialized already (BEGIN IMMEDIATE)."""

    @property
    def in_transaction(self) -> bool:
        return self.db.in_transaction

    def begin(self) -> None:
        self.db.execute("BEGIN IMMEDIATE")

    def commit(self) -> None:
        self.db.execute("COMMIT")

    def rollback(self) -> None:
        if self.db.in_transaction:
            self.db.execute("ROLLBACK")

    def close(self) -> None:
        self.db.close()


class PostgreSQLPool:
    """The pool in a PostgreSQL database (`name`: its URL without a password)."""

    row_lock = " FOR UPDATE SKIP LOCKED"   # a row another robot is writing is not claimable

    def __init__(self, url: str, tables: Sequence[str]) -> None:
        import psycopg2   # only where PostgreSQL is used
        self._psycopg2, self.url = psycopg2, url
        self.name = without_password(url)
        self._tables = tuple(statement.replace(" REAL", " DOUBLE PRECISION")
                             .replace(" INTEGER", " BIGINT") for statement in tables)
        self._expected = {table: tuple(column[0] for column in columns)
                          for table, columns in expected_columns(tables).items()}
        self.db: Any = None   # a psycopg2 connection (untyped), None while disconnected
        self.in_transaction = False
        self._retry_at, self._refused = 0.0, ""   # when to try connecting again, and why not
        self._connect()

    @staticmethod
    def is_integer(_column: str) -> str:
        return "TRUE"   # columns are typed

    def run(self, sql: str, args: Sequence[object] = ()) -> Rows:
        cursor = self._connection().cursor()
        try:
            cursor.execute(sql.replace("?", "%s"), args)
        except (self._psycopg2.OperationalError, self._psycopg2.InterfaceError) as error:
            raise self._unavailable(error) from error
        return cursor

    def serialize(self) -> None:
        """Writes that read before they insert wait for each other (until the commit)."""
        self.run("LOCK TABLE pool_ids IN EXCLUSIVE MODE")

    def begin(self) -> None:
        self.run("BEGIN")
        self.in_transaction = True

    def commit(self) -> None:
        self.run("COMMIT")
        self.in_transaction = False

    def rollback(self) -> None:
        """End the transaction with nothing written (also on a lost connection)."""
        self.in_transaction = False
        if self.db is not None and not self.db.closed:
            try:
                self.db.cursor().execute("ROLLBACK")
            except (self._psycopg2.OperationalError, self._psycopg2.InterfaceError):
                self._drop()

    def close(self) -> None:
        self._drop()

    def _connection(self) -> Any:
        if self.db is None or self.db.closed:
            if self.in_transaction:
                raise PoolUnavailable(f"fleet pool {self.name}: the connection was lost inside "
                                      "a transaction (nothing of it was written)")
            self._connect()
        return self.db

    def _connect(self) -> None:
        self._drop()
        started = time.monotonic()
        if started < self._retry_at:
            raise PoolUnavailable(self._refused)
        try:
            self.db = self._psycopg2.connect(self.url, **_PG_CONNECT)
        except self._psycopg2.Error as error:
            pause = 2 * (time.monotonic() - started)
            self._retry_at = started + 1.5 * pause
            failed = self._unavailable(error, f"connecting again {pause:.1f} s after this")
            self._refused = str(failed)
            raise failed from error
        self.db.autocommit = True   # BEGIN ... COMMIT where a transaction is meant
        try:
            with self.db.cursor() as cursor:
                cursor.execute("BEGIN")
                cursor.execute("SELECT pg_advisory_xact_lock(%s)", (_SCHEMA_LOCK,))
                self._check_foreign(cursor)
                for statement in self._tables:
                    cursor.execute(statement)
                cursor.execute("COMMIT")
        except FleetPoolError:
            self._drop()
            raise
        except self._psycopg2.Error as error:
            self._drop()
            raise self._unavailable(error) from error

    def _check_foreign(self, cursor: Any) -> None:
        cursor.execute("SELECT table_name, column_name FROM information_schema.columns WHERE "
                       "table_schema = current_schema() ORDER BY table_name, ordinal_position")
        found: dict[str, tuple[str, ...]] = {}
        for table, column in cursor.fetchall():
            found[table] = found.get(table, ()) + (column,)
        foreign = sorted(name for name, columns in found.items()
                         if self._expected.get(name) != columns)
        if foreign:
            raise FleetPoolError(
                f"fleet pool {self.name}: not a fleet pool: holds tables {sorted(found)} ("
                f"{', '.join(foreign)} not as in the pool's {', '.join(sorted(self._expected))}"
                "); refusing to use it, the database is left untouched")

    def _unavailable(self, error: Exception,
                     then: str = "the next call connects again") -> PoolUnavailable:
        if self.db is not None and self.db.closed:
            self._drop()
        reason = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        return PoolUnavailable(f"fleet pool {self.name}: unavailable ({reason}); {then}")

    def _drop(self) -> None:

        if self.db is not None:
            try:
                self.db.close()
            except self._psycopg2.Error:
                pass
        self.db = None
