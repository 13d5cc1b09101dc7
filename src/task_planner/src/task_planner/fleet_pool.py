"""The instructions a fleet shares, claimed under leases, ROS-free.

Several executors serve one pool of instructions, kept in an SQLite file (WAL: processes on one
host) or in a PostgreSQL database (robots on several hosts), chosen by where the pool is: a path or
`sqlite:///abs/path`, or `postgresql://[user@]host[:port]/database` (fleet_pool_db). An executor
that receives an instruction `share`s it; the others take it in with `since`. Ids a sender leaves
to the fleet come from `next_id`, one counter for the fleet, so two robots never give two
instructions one id.

A robot claims an instruction before it drives there: the claim is one transaction that locks the
instruction's row (SQLite: the whole file) and succeeds only while nobody holds the instruction, so
no two robots ever hold it at once. A claim is a lease of `lease_s` seconds, renewed by its robot
while it works (`renew`); a robot that dies stops renewing, and once its lease has run out the
instruction is claimable again, so nothing it held is lost. `complete` and `fail` close an
instruction only for the robot whose lease still holds it: a robot that lost its lease (stalled
past it, the instruction served by another) is told so (`LeaseLost`) and must not serve it, so
nothing is served twice. `cancel` closes an open instruction for every robot. Corridors (narrow
places) are held the same way, one robot at a time (`enter`, `leave`), under the robot's lease.
Each robot `report`s where it will be free next and from when, under its lease too, so a fleet
allocator running on every robot sees the same fleet (`robots`). A restarted executor gives back
whatever it held before (`release_all`) and closes in the pool what its journal closed while the
pool did not learn of it (`settle`: it stopped between the two writes). Times, leases included, are
passed in by the caller [s] (wall or ROS time, one clock for the fleet), on PostgreSQL too: the
fleet runs on ROS time, simulated (/clock) in simulation, which the database server's clock does
not follow. A PostgreSQL server that cannot be reached raises PoolUnavailable (a FleetPoolError)
naming it; the next call connects again.

A pool row whose instruction does not load (not JSON, a field of the wrong kind or unknown, an
instruction Instruction refuses: written by hand or damaged) is skipped by `since` and kept in
`quarantined` with the reason; the robots go on with the others.
"""
import json
from collections.abc import Iterable, Sequence
from dataclasses import asdict, dataclass
from types import TracebackType
from typing import Literal

from task_planner.fleet_pool_db import (FleetPoolError, PoolUnavailable,  # noqa: F401 (theirs too)
                                        PostgreSQLPool, Rows, SQLitePool, open_pool_db)
from task_planner.instruction import Instruction, InvalidInstruction
from task_planner.journal_rows import fields_problem

OPEN, CLAIMED, DONE, FAILED, CANCELLED = range(5)
STATE_NAMES = ("open", "claimed", "done", "failed", "cancelled")
CLOSED_STATES = (DONE, FAILED, CANCELLED)
_TABLES = ("CREATE TABLE IF NOT EXISTS pool (id INTEGER PRIMARY KEY, state INTEGER NOT NULL, "
           "robot TEXT NOT NULL, lease_until REAL NOT NULL, completion_time REAL NOT NULL, "
           "claims INTEGER NOT NULL, seq INTEGER NOT NULL, instruction TEXT NOT NULL, "
           "place INTEGER NOT NULL)",
           "CREATE TABLE IF NOT EXISTS pool_ids (last INTEGER NOT NULL)",
           "CREATE TABLE IF NOT EXISTS corridors (name TEXT PRIMARY KEY, robot TEXT NOT NULL, "
           "lease_until REAL NOT NULL)",
           "CREATE TABLE IF NOT EXISTS robots (robot TEXT PRIMARY KEY, node INTEGER NOT NULL, "
           "free_at REAL NOT NULL, lease_until REAL NOT NULL)")


class LeaseLost(RuntimeError):
    """The robot no longer holds the instruction: its lease ran out (or it never held it)."""


@dataclass(frozen=True)
class PoolEntry:
    id: int
    state: int
    robot: str            # who holds it (CLAIMED) or closed it (DONE, FAILED, CANCELLED)
    lease_until: float    # [s]
    completion_time: float
    claims: int           # how often it was claimed (more than 1: a lease ran out)


class FleetPool:
    """One fleet's shared instructions and their claims at `where`: an SQLite file's path (or
    ':memory:', or sqlite:///abs/path) or a PostgreSQL URL (`synchronous`: SQLite's PRAGMA)."""

    def __init__(self, where: object, lease_s: float = 10.0, synchronous: str = "FULL") -> None:
        if not lease_s > 0:
            raise FleetPoolError(f"lease_s must be > 0, got {lease_s}")
        self.lease_s = float(lease_s)
        self._db = open_pool_db(where, _TABLES, synchronous)
        self.path = self._db.name   # names the pool in messages (a URL without its password)
        self.quarantined: dict[int, str] = {}   # id -> reason of the pool rows `since` skipped

    def close(self) -> None:
        self._db.close()

    def _run(self, sql: str, args: Sequence[object] = ()) -> Rows:
        return self._db.run(sql, args)

    # ---- instructions ----

    def next_id(self, above: int = 0) -> int:
        """A fresh id for the fleet: more than every id handed out or shared, and than `above`."""
        with self._write():
            self._db.serialize()
            last = self._run(f"SELECT COALESCE(MAX(last), 0) FROM pool_ids WHERE "
                             f"{self._db.is_integer('last')}").fetchone()[0]
            largest = self._run("SELECT COALESCE(MAX(id), 0) FROM pool").fetchone()[0]
            new = max(last, largest, int(above)) + 1
            self._run("DELETE FROM pool_ids")
            self._run("INSERT INTO pool_ids VALUES (?)", (new,))
            return new

    def share(self, instructions: Iterable[Instruction]) -> dict[int, str]:
        """Put instructions into the pool for every robot. Returns {id: reason} for those refused:
        the pool holds another instruction under that id. One already there is left as it is."""
        refused: dict[int, str] = {}
        with self._write():
            self._db.serialize()   # sequence numbers in commit order: `since` misses none
            seq = self._run("SELECT COALESCE(MAX(seq), 0) FROM pool").fetchone()[0]
            for instruction in instructions:
                text, shared = _encode(instruction), self._shared(instruction.id)
                if shared is not None:
                    if shared != text:
                        refused[instruction.id] = _conflict(instruction.id)
                    continue
                seq += 1
                self._run("INSERT INTO pool VALUES (?, ?, '', 0, 0, 0, ?, ?, -1)",
                          (instruction.id, OPEN, seq, text))
        return refused

    def conflicting(self, instructions: Iterable[Instruction]) -> dict[int, str]:
        """{id: reason} of the instructions `share` would refuse (read only)."""
        return {i.id: _conflict(i.id) for i in instructions
                if self._shared(i.id) not in (None, _encode(i))}

    def _shared(self, instruction_id: int) -> str | None:
        row = self._run("SELECT instruction FROM pool WHERE id=?",
                        (int(instruction_id),)).fetchone()
        return None if row is None else row[0]

    def since(self, seq: int) -> tuple[int, list[Instruction]]:
        """(latest seq, [Instruction shared after `seq`]), in the order they were shared; a row
        that does not load is left out and kept in `quarantined`."""
        rows = self._run(f"SELECT seq, id, instruction FROM pool WHERE seq>? AND "
                         f"{self._db.is_integer('seq')} ORDER BY seq", (int(seq),)).fetchall()
        shared: list[Instruction] = []
        for _, instruction_id, text in rows:
            try:
                shared.append(_decode(text))
            except FleetPoolError as error:
                self.quarantined[instruction_id] = (f"quarantined: fleet pool row "
                                                    f"{instruction_id} is no valid instruction: "
                                                    f"{error}")
        return (rows[-1][0] if rows else int(seq)), shared

    # ---- claims ----

    def claimable(self, now: float) -> list[int]:
        """Ids nobody holds at `now` (open, or claimed under a lease that has run out)."""
        rows = self._run("SELECT id FROM pool WHERE state=? OR (state=? AND lease_until<?) "
                         "ORDER BY id", (OPEN, CLAIMED, now))
        return [row[0] for row in rows]

    def held_by_others(self, robot: str, now: float) -> set[int]:
        """Ids another robot holds at `now` (claimed under a lease that still runs)."""
        rows = self._run("SELECT id FROM pool WHERE state=? AND robot<>? AND lease_until>=?",
                         (CLAIMED, robot, now))
        return {row[0] for row in rows}

    def places_held_by_others(self, robot: str, now: float) -> set[int]:
        """Places (graph nodes) where another robot serves, or drives to serve, what it holds."""
        rows = self._run("SELECT DISTINCT place FROM pool WHERE state=? AND robot<>? AND "
                         "lease_until>=? AND place>=0", (CLAIMED, robot, now))
        return {row[0] for row in rows}

    def closed(self, ids: Iterable[int]) -> dict[int, PoolEntry]:
        """{id: PoolEntry} of those of `ids` that are closed (done, failed or cancelled)."""
        found: dict[int, PoolEntry] = {}
        wanted = [int(i) for i in ids]
        for start in range(0, len(wanted), 500):   # SQLite's limit on bound variables
            part = wanted[start:start + 500]
            rows = self._run(
                f"SELECT id, state, robot, lease_until, completion_time, claims FROM pool WHERE "
                f"state IN (?, ?, ?) AND id IN ({','.join('?' * len(part))})",
                CLOSED_STATES + tuple(part))
            found.update((row[0], PoolEntry(*row)) for row in rows)
        return found

    def claim(self, robot: str, instruction_id: int, now: float, place: int = -1) -> bool:
        """True when `robot` now holds the instruction (until now + lease_s), to serve it at
        `place` (a graph node; -1: not said); False when another robot holds it, it is closed or
        not in the pool (or another robot's transaction writes it just now). Claiming what the
        robot holds renews it."""
        _check_robot(robot)
        with self._write():
            if self._run(f"SELECT id FROM pool WHERE id=?{self._db.row_lock}",
                         (int(instruction_id),)).fetchone() is None:
                return False
            changed = self._run(
                "UPDATE pool SET claims=claims+CAST((robot<>? OR state<>? OR lease_until<?) AS "
                "INTEGER), state=?, "
                "robot=?, lease_until=?, place=? WHERE id=? AND (state=? OR (state=? AND "
                "(lease_until<? OR robot=?)))",
                (robot, CLAIMED, now, CLAIMED, robot, now + self.lease_s, int(place),
                 int(instruction_id), OPEN, CLAIMED, now, robot))
            return changed.rowcount == 1

    def renew(self, robot: str, now: float, ids: Iterable[int] = (),
              corridors: Iterable[str] = ()) -> list[int]:
        """Extend the leases `robot` still holds at `now` on the instructions `ids` and the
        corridors `corridors` (only those: a claim left over from before a restart is never kept
        alive); returns those of `ids` it holds."""
        _check_robot(robot)
        wanted, names = [int(i) for i in ids], list(corridors)
        with self._write():
            held = []
            for instruction_id in wanted:
                changed = self._run(
                    "UPDATE pool SET lease_until=? WHERE id=? AND robot=? AND state=? AND "
                    "lease_until>=?", (now + self.lease_s, instruction_id, robot, CLAIMED, now))
                if changed.rowcount == 1:
                    held.append(instruction_id)
            for name in names:
                self._run("UPDATE corridors SET lease_until=? WHERE name=? AND robot=? AND "
                          "lease_until>=?", (now + self.lease_s, name, robot, now))
            return held

    def release_all(self, robot: str) -> None:
        """Give back every instruction and corridor `robot` holds (a restarted executor starts
        from its journal, not from claims it made before)."""
        _check_robot(robot)
        with self._write():
            self._run("UPDATE pool SET state=?, robot='', lease_until=0 WHERE robot=? AND "
                      "state=?", (OPEN, robot, CLAIMED))
            self._run("DELETE FROM corridors WHERE robot=?", (robot,))

    def settle(self, robot: str, instruction_id: int, now: float, state: int) -> bool:
        """Close an instruction `robot`'s journal closed (`state`: DONE, FAILED or CANCELLED) that
        the pool still holds open or claimed by that robot (it stopped between the two writes);
        True when it did."""
        _check_robot(robot)
        if state not in CLOSED_STATES:
            raise FleetPoolError(f"instruction {instruction_id}: cannot settle it as state "
                                 f"{state}")
        with self._write():
            changed = self._run(
                "UPDATE pool SET state=?, robot=?, completion_time=? WHERE id=? AND (state=? OR "
                "(state=? AND robot=?))",
                (state, robot, now, int(instruction_id), OPEN, CLAIMED, robot))
            return changed.rowcount == 1

    def complete(self, robot: str, instruction_id: int, now: float) -> None:
        """Close the instruction as served by `robot`; LeaseLost unless it holds it at `now`."""
        self._close_held(robot, instruction_id, now, DONE)

    def fail(self, robot: str, instruction_id: int, now: float) -> None:
        """Close the instruction as failed by `robot` (no other robot tries it again); LeaseLost
        unless it holds it at `now`."""
        self._close_held(robot, instruction_id, now, FAILED)

    def cancel(self, robot: str, instruction_id: int, now: float) -> bool:
        """Close an instruction that is not yet closed as cancelled through `robot`, whoever
        holds it; False when it is closed already or not in the pool."""
        _check_robot(robot)
        with self._write():
            changed = self._run(
                "UPDATE pool SET state=?, robot=?, completion_time=? WHERE id=? AND state IN "
                "(?, ?)", (CANCELLED, robot, now, int(instruction_id), OPEN, CLAIMED))
            return changed.rowcount == 1

    def enter(self, robot: str, names: Sequence[str], now: float) -> str:
        """Hold every corridor of `names` for `robot` (all or none); "" when it does, else the
        robot that holds one of them (its lease still running)."""
        _check_robot(robot)
        with self._write():
            self._db.serialize()   # two robots never both find a corridor free
            for name in names:
                row = self._run("SELECT robot FROM corridors WHERE name=? AND robot<>? AND "
                                "lease_until>=?", (name, robot, now)).fetchone()
                if row is not None:
                    return row[0]
            for name in names:
                self._run("INSERT INTO corridors VALUES (?, ?, ?) ON CONFLICT (name) DO UPDATE "
                          "SET robot=excluded.robot, lease_until=excluded.lease_until",
                          (name, robot, now + self.lease_s))
        return ""

    def leave(self, robot: str, keep: Iterable[str] = ()) -> None:
        """Give up every corridor `robot` holds but those in `keep`."""
        _check_robot(robot)
        with self._write():
            for (name,) in self._run("SELECT name FROM corridors WHERE robot=?",
                                     (robot,)).fetchall():
                if name not in keep:
                    self._run("DELETE FROM corridors WHERE name=?", (name,))

    def report(self, robot: str, node: int, free_at: float, now: float) -> None:
        """`robot` will be free at graph node `node` from `free_at` [s]; the report holds until
        now + lease_s (a robot that stops reporting drops out of `robots`)."""
        _check_robot(robot)
        with self._write():
            self._run("INSERT INTO robots VALUES (?, ?, ?, ?) ON CONFLICT (robot) DO UPDATE SET "
                      "node=excluded.node, free_at=excluded.free_at, "
                      "lease_until=excluded.lease_until",
                      (robot, int(node), float(free_at), now + self.lease_s))

    def robots(self, now: float) -> dict[str, tuple[int, float]]:
        """{robot: (node, free_at)} of the robots whose report still holds at `now`."""
        return {row[0]: (row[1], row[2]) for row in self._run(
            "SELECT robot, node, free_at FROM robots WHERE lease_until>=? ORDER BY robot",
            (now,))}

    def release(self, robot: str, instruction_id: int) -> None:
        """Give a held instruction back to the pool (the robot will not serve it)."""
        with self._write():
            self._run("UPDATE pool SET state=?, robot='', lease_until=0 WHERE id=? AND robot=? "
                      "AND state=?", (OPEN, int(instruction_id), robot, CLAIMED))

    def entries(self) -> list[PoolEntry]:
        """Every PoolEntry, by id."""
        return [PoolEntry(*row) for row in self._run(
            "SELECT id, state, robot, lease_until, completion_time, claims FROM pool ORDER BY id")]

    def _close_held(self, robot: str, instruction_id: int, now: float, state: int) -> None:
        _check_robot(robot)
        with self._write():
            changed = self._run(
                "UPDATE pool SET state=?, completion_time=? WHERE id=? AND robot=? AND state=? "
                "AND lease_until>=?", (state, now, int(instruction_id), robot, CLAIMED, now))
            if changed.rowcount != 1:
                raise LeaseLost(f"robot {robot!r} does not hold instruction {instruction_id} "
                                f"at {now:.3f} s: {self._describe(instruction_id)}")

    def _describe(self, instruction_id: int) -> str:
        row = self._run("SELECT state, robot, lease_until FROM pool WHERE id=?",
                        (int(instruction_id),)).fetchone()
        if row is None:
            return "not in the pool"
        state, robot, until = row
        if state == CLAIMED:
            return f"held by {robot!r} until {until:.3f} s"
        if state not in range(len(STATE_NAMES)):
            return f"in the unknown state {state!r}"
        return STATE_NAMES[state] + (f" by {robot!r}" if robot else "")

    def transaction(self) -> "_Transaction":
        """A context in which this connection's writes form one transaction: the other robots
        see all of them at its end or none (e.g. instructions shared with the claim on one)."""
        return _Transaction(self._db)

    def _write(self) -> "_Transaction":
        return _Transaction(self._db)


class _Transaction:
    """BEGIN ... COMMIT (ROLLBACK on error; SQLite: BEGIN IMMEDIATE, the write lock taken at the
    start, so a read-then-update cannot interleave with another process's). Inside an open
    transaction it joins that one."""

    def __init__(self, db: SQLitePool | PostgreSQLPool) -> None:
        self.db, self.outer = db, False

    def __enter__(self) -> None:
        self.outer = not self.db.in_transaction
        if self.outer:
            self.db.begin()

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 trace: TracebackType | None) -> Literal[False]:
        if not self.outer:
            return False
        if kind is None:
            try:
                self.db.commit()
            except Exception:   # e.g. disk full: never leave the write lock held
                self.db.rollback()
                raise
        else:
            self.db.rollback()
        return False


def _conflict(instruction_id: int) -> str:
    return (f"instruction {instruction_id}: the fleet pool holds another instruction under this "
            "id (let the fleet choose: id 0)")


def _encode(instruction: Instruction) -> str:
    return json.dumps(asdict(instruction), sort_keys=True)


def _decode(text: str) -> Instruction:
    """The Instruction of a pool row's JSON; FleetPoolError naming what is wrong with it."""
    try:
        values = json.loads(text)
    except (TypeError, ValueError) as error:   # NULL, a BLOB that is no UTF-8, not JSON
        raise FleetPoolError(f"column instruction holds {text!r:.40}, not an instruction in "
                             f"JSON ({error})") from None
    problem = fields_problem(values)
    if problem:
        raise FleetPoolError(problem)
    try:
        return Instruction(**values)
    except InvalidInstruction as error:
        raise FleetPoolError(str(error)) from None


def _check_robot(robot: object) -> None:

    if not isinstance(robot, str) or not robot:
        raise FleetPoolError(f"a robot is named by a non-empty string, got {robot!r}")
