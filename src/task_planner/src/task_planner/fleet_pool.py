"""The instructions a fleet shares, claimed under leases in one SQLite file (WAL), ROS-free.

Several executors (processes on one host: SQLite's WAL needs shared memory, so the file must not
sit on a network file system) serve one pool of instruction ids. A robot claims an instruction
before it drives there: the claim is one `BEGIN IMMEDIATE` transaction that succeeds only while
nobody holds the instruction, so no two robots ever hold it at once. A claim is a lease of
`lease_s` seconds, renewed by its robot while it works (`renew`); a robot that dies stops
renewing, and once its lease has run out the instruction is claimable again, so nothing it held
is lost. `complete` closes an instruction only for the robot whose lease still holds it: a robot
that lost its lease (stalled past it, the instruction served by another) is told so
(`LeaseLost`) and must not serve it, so nothing is served twice. Times are passed in by the
caller [s] (wall or ROS time, one clock for the fleet).
"""
from dataclasses import dataclass

from task_planner.journal_file import JournalFileError, open_journal

OPEN, CLAIMED, DONE = range(3)
STATE_NAMES = ("open", "claimed", "done")
BUSY_TIMEOUT_MS = 10000   # how long a write waits for another process's transaction
_TABLE = ("CREATE TABLE IF NOT EXISTS pool (id INTEGER PRIMARY KEY, state INTEGER NOT NULL, "
          "robot TEXT NOT NULL, lease_until REAL NOT NULL, completion_time REAL NOT NULL, "
          "claims INTEGER NOT NULL)")


class LeaseLost(RuntimeError):
    """The robot no longer holds the instruction: its lease ran out (or it never held it)."""


class FleetPoolError(ValueError):
    """The pool's file or a request to it is unusable; the message names it."""


@dataclass(frozen=True)
class PoolEntry:
    id: int
    state: int
    robot: str            # who holds it (CLAIMED) or served it (DONE); empty when never claimed
    lease_until: float    # [s]
    completion_time: float
    claims: int           # how often it was claimed (more than 1: a lease ran out)


class FleetPool:
    """One fleet's shared instruction ids and their claims; `path` may be ':memory:'."""

    def __init__(self, path, lease_s=10.0, synchronous="FULL"):
        if not lease_s > 0:
            raise FleetPoolError(f"lease_s must be > 0, got {lease_s}")
        self.lease_s = float(lease_s)
        try:
            self._db = open_journal(str(path), synchronous, (_TABLE,), "fleet pool")
        except JournalFileError as error:
            raise FleetPoolError(str(error)) from error
        self._db.execute(f"PRAGMA busy_timeout={BUSY_TIMEOUT_MS}")

    def close(self):
        self._db.close()

    def add(self, ids):
        """Put instruction ids into the pool (ids already there are left as they are)."""
        with self._write():
            self._db.executemany(
                "INSERT OR IGNORE INTO pool VALUES (?, ?, '', 0, 0, 0)",
                [(int(i), OPEN) for i in ids])

    def claimable(self, now):
        """Ids nobody holds at `now` (open, or claimed under a lease that has run out)."""
        rows = self._db.execute("SELECT id FROM pool WHERE state=? OR (state=? AND lease_until<?) "
                                "ORDER BY id", (OPEN, CLAIMED, now))
        return [row[0] for row in rows]

    def claim(self, robot, instruction_id, now):
        """True when `robot` now holds the instruction (until now + lease_s); False when another
        robot holds it or it is done."""
        _check_robot(robot)
        with self._write():
            changed = self._db.execute(
                "UPDATE pool SET state=?, robot=?, lease_until=?, claims=claims+1 WHERE id=? "
                "AND (state=? OR (state=? AND lease_until<?))",
                (CLAIMED, robot, now + self.lease_s, int(instruction_id), OPEN, CLAIMED, now))
            return changed.rowcount == 1

    def renew(self, robot, now):
        """Extend every lease `robot` still holds at `now`; returns the ids it holds."""
        _check_robot(robot)
        with self._write():
            self._db.execute("UPDATE pool SET lease_until=? WHERE robot=? AND state=? AND "
                             "lease_until>=?", (now + self.lease_s, robot, CLAIMED, now))
            rows = self._db.execute("SELECT id FROM pool WHERE robot=? AND state=? AND "
                                    "lease_until>=? ORDER BY id", (robot, CLAIMED, now))
            return [row[0] for row in rows]

    def complete(self, robot, instruction_id, now):
        """Close the instruction as served by `robot`; LeaseLost unless it holds it at `now`."""
        _check_robot(robot)
        with self._write():
            changed = self._db.execute(
                "UPDATE pool SET state=?, completion_time=? WHERE id=? AND robot=? AND state=? "
                "AND lease_until>=?", (DONE, now, int(instruction_id), robot, CLAIMED, now))
            if changed.rowcount != 1:
                raise LeaseLost(f"robot {robot!r} does not hold instruction {instruction_id} "
                                f"at {now:.3f} s: {self._describe(instruction_id)}")

    def release(self, robot, instruction_id):
        """Give a held instruction back to the pool (the robot will not serve it)."""
        with self._write():
            self._db.execute("UPDATE pool SET state=?, robot='', lease_until=0 WHERE id=? AND "
                             "robot=? AND state=?", (OPEN, int(instruction_id), robot, CLAIMED))

    def entries(self):
        """Every PoolEntry, by id."""
        return [PoolEntry(*row) for row in self._db.execute("SELECT * FROM pool ORDER BY id")]

    def _describe(self, instruction_id):
        row = self._db.execute("SELECT state, robot, lease_until FROM pool WHERE id=?",
                               (int(instruction_id),)).fetchone()
        if row is None:
            return "not in the pool"
        state, robot, until = row
        if state == CLAIMED:
            return f"held by {robot!r} until {until:.3f} s"
        return STATE_NAMES[state] + (f" by {robot!r}" if robot else "")

    def _write(self):
        return _Transaction(self._db)


class _Transaction:
    """BEGIN IMMEDIATE ... COMMIT (ROLLBACK on error): the write lock is taken at the start, so
    a read-then-update cannot interleave with another process's."""

    def __init__(self, db):
        self.db = db

    def __enter__(self):
        self.db.execute("BEGIN IMMEDIATE")

    def __exit__(self, kind, error, trace):
        self.db.execute("COMMIT" if kind is None else "ROLLBACK")
        return False


def _check_robot(robot):
    if not isinstance(robot, str) or not robot:
        raise FleetPoolError(f"a robot is named by a non-empty string, got {robot!r}")

