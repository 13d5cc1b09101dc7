"""The task buffer of thesis 000 Fig. 4-14, journalled in SQLite (stdlib sqlite3, WAL mode).

Perceptions become instructions that are written into the task buffer; the task planner fetches
them; the result is written back. Every instruction is committed to the journal before `submit`
returns, so an acknowledgement is never lost. Life cycle (tamp_msgs/InstructionState):

    PENDING -> ACTIVE -> DONE | FAILED | CANCELLED     (PENDING -> FAILED | CANCELLED too)

ACTIVE means the robot function is being executed at the destination. Opening an existing journal
puts ACTIVE rows back to PENDING (the function was interrupted, so it never completed) and keeps
every DONE row closed, so a restart loses nothing and repeats nothing that finished. Times are
passed in by the caller (ROS time in the node, simulated time in tests) [s].

Chains (Table 4-1 `previous_id`): a successor is eligible once its predecessor is DONE. The buffer
keeps every instruction it ever journalled, so a predecessor it does not hold has not arrived yet
(a chain's messages may arrive in any order): the successor waits for it, at most
`predecessor_wait_s` after it was received; then `fail_missing_predecessors` fails it with a reason
naming the missing predecessor. When a predecessor fails or is cancelled its open successors fail
too, with a reason naming it. `version` counts changes.

Ids: `next_id` is one more than the largest id (or `previous_id`) ever journalled, read from the
journal on opening, so a sender that lets the buffer choose (the executor node's
/task_planner/submit with id 0) never gets an id used before, across restarts too.

Snapshots for publishing: the buffer keeps, besides every record, the open ones, the ids of the
`recent_finished` most recently finished ones and the count per state, so `snapshot` and `counts`
cost O(open + recent_finished), not O(every record ever journalled).

At the door `submit` refuses (TaskBufferError naming the instruction) besides a reused id and a
chain cycle: a function that is no robot function (with `functions`), a destination outside the
graph, a destination_name that names another node than `destination` (with `place_names`), and a
start_time more than `future_tolerance_s` after `now`.
The instruction's own fields are checked by Instruction (finite numbers, bounds).

Quarantine: opening a journal leaves out every row that does not load, with the reason in
`quarantined`: a column holding NULL, text for a number or a BLOB for text, an unknown state
(journal_rows), an instruction Instruction refuses, or one the door would refuse for its function
or destination. An open one is FAILED with the reason, so it is never run; its id stays used.
"""
import sqlite3
from collections import deque
from collections.abc import Container, Iterable, Iterator
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any, overload

from task_planner.executor_commands import Search
from task_planner.instruction import Instruction, InvalidInstruction
from task_planner.journal_file import JournalFileError, open_journal
from task_planner.journal_rows import column_problem
from task_planner.reward import decayed_reward



# a journalled search: (instruction_id, target, start_s, end_s, found, [place names])
JournalledSearch = tuple[int, str, float, float, bool, list[str]]

JOURNAL_FAILED = "not journalled, so not accepted"  # a refusal for a failed write

PENDING, ACTIVE, DONE, FAILED, CANCELLED = range(5)  # = tamp_msgs/InstructionState constants
STATE_NAMES = ("pending", "active", "done", "failed", "cancelled")
OPEN_STATES = (PENDING, ACTIVE)

_INSTRUCTION_FIELDS = tuple(f.name for f in fields(Instruction))
_COLUMNS = ("id INTEGER PRIMARY KEY, previous_id INTEGER, gamma REAL, beta REAL, "
            "destination INTEGER, type INTEGER, start_time REAL, duration INTEGER, source TEXT, "
            "target TEXT, status INTEGER, function INTEGER, destination_name TEXT, text TEXT, "
            "state INTEGER NOT NULL, received_time REAL NOT NULL, started_time REAL NOT NULL, "
            "completion_time REAL NOT NULL, reward_earned REAL NOT NULL, reason TEXT NOT NULL, "
            "seq INTEGER NOT NULL")


class TaskBufferError(ValueError):
    """A request to the task buffer that breaks its rules; the message names the instruction."""


@dataclass(frozen=True)
class BufferConfig:
    """Journal settings."""

    synchronous: str = "FULL"  # SQLite PRAGMA synchronous: FULL survives power loss in WAL mode
    node_count: int = 0        # graph size for destination checks; 0 = do not check
    place_names: tuple[str, ...] = ()  # graph place names, index = node id, for
                               # destination_name checks; () = do not check
    future_tolerance_s: float = 5.0    # a start_time this far after the receiving clock is
                                       # still accepted (clocks of two machines) [s]
    predecessor_wait_s: float = 300.0  # a successor whose predecessor has not arrived this long
                                       # after it was received fails [s]
    recent_finished: int = 50  # finished records `snapshot` holds besides the open ones
    functions: tuple[tuple[int, str], ...] = ()  # (code, name) of each robot function, for
                               # function checks; () = do not check


@dataclass(frozen=True)
class Record:
    """One instruction and its life-cycle state (tamp_msgs/InstructionState)."""

    instruction: Instruction
    state: int
    received_time: float    # when the buffer journalled it [s]
    started_time: float     # when it became ACTIVE last [s]; 0 if never
    completion_time: float  # when it reached DONE/FAILED/CANCELLED [s]; 0 while open
    reward_earned: float    # Eq. 4-2 reward when DONE, else 0
    reason: str             # why it failed or was cancelled; empty otherwise
    seq: int                # arrival order in the buffer (oldest first)

    @property
    def is_open(self) -> bool:
        return self.state in OPEN_STATES


class TaskBuffer:
    """Instructions journalled in SQLite; `path` may be ':memory:' for a buffer without a file."""

    def __init__(self, path: str | Path, config: BufferConfig | None = None) -> None:
        self.config = config or BufferConfig()
        if self.config.synchronous not in ("OFF", "NORMAL", "FULL", "EXTRA"):
            raise TaskBufferError(f"synchronous must be OFF, NORMAL, FULL or EXTRA, "
                                  f"got {self.config.synchronous!r}")
        if self.config.recent_finished < 0:
            raise TaskBufferError(f"recent_finished must be >= 0, "
                                  f"got {self.config.recent_finished}")
        self.path = str(path)
        try:   # an unreadable or foreign file is refused untouched (journal_file)
            self._db = open_journal(self.path, self.config.synchronous, (
                f"CREATE TABLE IF NOT EXISTS instructions ({_COLUMNS})",
                # robot state that must survive a restart besides the instructions (battery)
                "CREATE TABLE IF NOT EXISTS robot_state "
                "(name TEXT PRIMARY KEY, value REAL NOT NULL)",
                # searches for people not where they were believed (executor), for reports
                "CREATE TABLE IF NOT EXISTS searches (instruction_id INTEGER NOT NULL, "
                "target TEXT NOT NULL, start_s REAL NOT NULL, end_s REAL NOT NULL, "
                "found INTEGER NOT NULL, places TEXT NOT NULL)"))
        except JournalFileError as error:
            raise TaskBufferError(str(error)) from error
        self.resumed = self._db.execute(
            "UPDATE instructions SET state=?, started_time=0 WHERE state=?",
            (PENDING, ACTIVE)).rowcount
        self._build_index()
        self.version = 0  # incremented by every change (for publishing snapshots on change)

    def _build_index(self) -> None:
        """The in-memory views of the journal (at start, and after a failed write)."""
        self.quarantined: list[tuple[int, str]] = []  # (id, reason) of journal rows that do not
        #                                               load
        self._records = {row.instruction.id: row for row in self._load()}  # in seq order
        self._open = {i: r for i, r in self._records.items() if r.is_open}   # in seq order
        self._done = {i for i, r in self._records.items() if r.state == DONE}
        self._active = next((i for i, r in self._open.items() if r.state == ACTIVE), 0)
        self._next_seq = (self._db.execute("SELECT MAX(seq) FROM instructions WHERE "
                                           "typeof(seq) = 'integer'").fetchone()[0] or 0) + 1
        self._counts = [0] * len(STATE_NAMES)
        for record in self._records.values():
            self._counts[record.state] += 1
        self._total_reward = sum(r.reward_earned for r in self._records.values())
        self._max_id = max([max(r.instruction.id, r.instruction.previous_id)
                            for r in self._records.values()]
                           + [i for i, _ in self.quarantined], default=0)
        finished = sorted((r for r in self._records.values() if not r.is_open),
                          key=lambda r: (r.completion_time, r.seq))
        # ids of the most recently finished records, oldest first (maxlen drops the oldest)
        self._recent = deque((r.instruction.id for r in finished),
                             maxlen=self.config.recent_finished)
        # open successors whose predecessor had not arrived when last looked at (id -> record)
        self._awaiting = {i: r for i, r in self._open.items() if self._missing_predecessor(r)}

    def close(self) -> None:
        self._db.close()

    # ---- submit (perception -> task buffer) ----

    def submit(self, instruction: Instruction, now: float) -> Record:
        """Journal `instruction` (committed on return); returns its Record.

        Re-submitting an identical instruction returns the stored record unchanged. Raises
        TaskBufferError for an id reused with other content, an unknown function or destination, a
        destination_name of another node, a start_time in the future (beyond
        `future_tolerance_s` of `now` [s]), or a `previous_id` chain that would form a cycle.
        """
        record, error = self.submit_many([instruction], now)[0]
        if record is None:
            raise TaskBufferError(error)
        return record

    def submit_many(self, instructions: Iterable[Instruction],
                    now: float) -> list[tuple[Record | None, str]]:
        """Journal a burst in one transaction (one disk sync); bad ones are refused, not fatal.

        Returns [(Record, "")] or [(None, reason)] per instruction, in order.
        """
        results: list[tuple[Record | None, str]] = []
        try:
            with self._db:
                self._db.execute("BEGIN")
                for instruction in instructions:
                    try:
                        results.append((self._insert(instruction, now), ""))
                    except TaskBufferError as error:
                        results.append((None, str(error)))
        except sqlite3.Error as error:  # disk full, I/O error: the burst is rolled back
            try:
                if self._db.in_transaction:
                    self._db.rollback()
            except sqlite3.Error:
                pass                     # nothing more to undo than SQLite already did
            self._build_index()          # forget what memory took but the journal did not
            self.version += 1
            return [(None, f"instruction {i.id}: {JOURNAL_FAILED}: writing {self.path} "
                           f"failed: {error}") for i in instructions]
        return results

    def _insert(self, instruction: Instruction, now: float) -> Record:
        known = self._records.get(instruction.id)
        if known is not None:
            if known.instruction == instruction:
                return known
            raise TaskBufferError(f"instruction {instruction.id}: id already used by a different "
                                  f"instruction ({STATE_NAMES[known.state]})")
        self._check(instruction, now)
        record = Record(instruction, PENDING, float(now), 0.0, 0.0, 0.0, "", self._next_seq)
        predecessor = self._records.get(instruction.previous_id)
        if predecessor is not None and predecessor.state in (FAILED, CANCELLED):
            record = _close(record, FAILED, now, f"predecessor {predecessor.instruction.id} "
                                                  f"{STATE_NAMES[predecessor.state]}")
        self._db.execute("INSERT INTO instructions VALUES (" + ",".join("?" * 21) + ")",
                         _row(record))
        self._index(record)
        if record.is_open and self._missing_predecessor(record):
            self._awaiting[instruction.id] = record
        self._next_seq += 1
        self.version += 1
        return record

    def _check(self, instruction: Instruction, now: float) -> None:
        problem = self._refusal(instruction)
        if problem:
            raise TaskBufferError(problem)
        ahead = instruction.start_time - now
        if ahead > self.config.future_tolerance_s:
            raise TaskBufferError(f"instruction {instruction.id}: start_time "
                                  f"{instruction.start_time:.3f} s is {ahead:.3f} s in the future "
                                  f"(received at {now:.3f} s; tolerance "
                                  f"{self.config.future_tolerance_s:g} s)")
        chain, current = [instruction.id], instruction.previous_id
        while current in self._records:
            if current in chain:  # only reachable through a corrupt journal
                raise TaskBufferError(f"instruction {instruction.id}: previous_id cycle via "
                                      f"{current}")
            chain.append(current)
            current = self._records[current].instruction.previous_id
        if current == instruction.id:
            raise TaskBufferError(f"instruction {instruction.id}: previous_id chain "
                                  f"{' -> '.join(map(str, chain))} returns to itself")

    def _refusal(self, instruction: Instruction) -> str:
        """Why the instruction's function or destination is refused (at the door, and on
        loading the journal), or ""."""
        functions = dict(self.config.functions)
        if functions and instruction.function not in functions:
            known = ", ".join(f"{code} {name}" for code, name in self.config.functions)
            return (f"instruction {instruction.id}: function {instruction.function} is no robot "
                    f"function (known: {known})")
        nodes = self.config.node_count
        if nodes and not 0 <= instruction.destination < nodes:
            return (f"instruction {instruction.id}: destination node {instruction.destination} "
                    f"is not in the graph (nodes 0..{nodes - 1})")
        names, name = self.config.place_names, instruction.destination_name
        if name and names and (not 0 <= instruction.destination < len(names)
                               or names[instruction.destination] != name):
            where = (f"node {names.index(name)}" if name in names else "no node of the graph")
            return (f"instruction {instruction.id}: destination_name {name!r} names {where}, "
                    f"not destination node {instruction.destination}")
        return ""

    # ---- fetch (task buffer -> planner) ----

    def get(self, instruction_id: int) -> Record:
        try:
            return self._records[instruction_id]
        except KeyError:
            raise TaskBufferError(f"instruction {instruction_id}: not in the task buffer") from None

    def holds(self, instruction_id: int) -> bool:
        """True when the buffer has journalled the instruction (in any state)."""
        return instruction_id in self._records

    def records(self) -> list[Record]:
        """Every record, oldest first (the dict keeps arrival order: seq only grows)."""
        return list(self._records.values())

    def snapshot(self) -> list[Record]:
        """The open records and the `recent_finished` most recently finished ones, oldest first
        (by arrival): O(open + recent_finished) however many records the journal holds."""
        recent = [self._records[i] for i in self._recent]
        return sorted(list(self._open.values()) + recent, key=lambda r: r.seq)

    def counts(self) -> tuple[int, ...]:
        """Number of records per state, indexed by the state constants (PENDING .. CANCELLED)."""
        return tuple(self._counts)

    def next_id(self, previous_id: int = 0) -> int:
        """The id for a new instruction whose sender lets the buffer choose: one more than every
        id and previous_id ever journalled (and than `previous_id`, the new one's predecessor)."""
        return max(self._max_id, previous_id) + 1

    def open_records(self) -> list[Record]:
        """The PENDING and ACTIVE records, oldest first."""
        return list(self._open.values())

    def eligible(self, record: Record) -> bool:
        """Table 4-1 `previous_id`: open, and no predecessor or a DONE one."""
        previous = record.instruction.previous_id
        return record.is_open and (previous == 0 or previous in self.done_ids())

    def done_ids(self) -> set[int]:
        """Ids of the DONE instructions (a live view kept by the buffer: do not modify)."""
        return self._done

    def active_id(self) -> int:
        """Id of the ACTIVE instruction; 0 when none is."""
        return self._active

    def total_reward(self) -> float:
        """Sum of the Eq. 4-2 rewards earned (kept as instructions finish)."""
        return self._total_reward

    # ---- robot state (executor) ----

    @overload
    def robot_value(self, name: str, default: float) -> float: ...

    @overload
    def robot_value(self, name: str, default: None = None) -> float | None: ...

    def robot_value(self, name: str, default: float | None = None) -> float | None:
        """A robot-state value stored with `store_robot_value`, or `default`."""
        row = self._db.execute("SELECT value FROM robot_state WHERE name=?", (name,)).fetchone()
        return default if row is None else row[0]

    def store_robot_value(self, name: str, value: float) -> None:
        """Keep `value` under `name` across restarts (written without a disk sync of its own:
        the next durable commit carries it; a power cut may lose the latest value)."""
        self._lazy_write("INSERT OR REPLACE INTO robot_state VALUES (?, ?)", (name, float(value)))

    def store_search(self, search: Search) -> None:
        """Journal a finished search: Search (task_planner.executor)."""
        self._lazy_write("INSERT INTO searches VALUES (?, ?, ?, ?, ?, ?)",
                         (search.instruction_id, search.target, search.start_s, search.end_s,
                          int(search.found), ",".join(search.places)))

    def searches(self) -> list[JournalledSearch]:
        """Every journalled search (see `journalled_searches`)."""
        return journalled_searches(self._db)

    # ---- write back (executor -> task buffer) ----

    def start(self, instruction_id: int, now: float) -> Record:
        """PENDING -> ACTIVE: the robot function begins. Only one instruction is active."""
        record = self._expect(instruction_id, (PENDING,), "start")
        if not self.eligible(record):
            raise TaskBufferError(f"instruction {instruction_id}: predecessor "
                                  f"{record.instruction.previous_id} is not done")
        active = self.active_id()
        if active:
            raise TaskBufferError(f"instruction {instruction_id}: instruction {active} is active")
        return self._store(_replace(record, state=ACTIVE, started_time=float(now)),
                           durable=False)

    def finish(self, instruction_id: int, now: float) -> Record:
        """ACTIVE -> DONE with the Eq. 4-2 reward gamma * beta ** (now - start_time)."""
        record = self._expect(instruction_id, (ACTIVE,), "finish")
        ins = record.instruction
        reward = float(decayed_reward(ins.gamma, ins.beta, max(0.0, now - ins.start_time)))
        return self._store(_replace(_close(record, DONE, now, ""), reward_earned=reward))

    def fail(self, instruction_id: int, now: float, reason: str) -> Record:
        """PENDING/ACTIVE -> FAILED with `reason`; open successors fail too."""
        if not reason:
            raise TaskBufferError(f"instruction {instruction_id}: a failure needs a reason")
        record = self._expect(instruction_id, OPEN_STATES, "fail")
        return self._close_chain(record, FAILED, now, reason)

    def cancel(self, instruction_id: int, now: float,
               reason: str = "cancelled by request") -> Record:
        """PENDING/ACTIVE -> CANCELLED; open successors fail naming it."""
        record = self._expect(instruction_id, OPEN_STATES, "cancel")
        return self._close_chain(record, CANCELLED, now, reason)

    def close_elsewhere(self, instruction_id: int, now: float, state: int, reason: str) -> Record:
        """An open instruction another robot of the fleet closed (fleet_link), with `reason`
        naming it: DONE earns this robot nothing (and lets a successor here start); FAILED and
        CANCELLED fail the open successors as `fail` and `cancel` do."""
        if not reason:
            raise TaskBufferError(f"instruction {instruction_id}: closing it needs a reason")
        record = self._expect(instruction_id, OPEN_STATES, "close")
        if state == DONE:
            return self._store(_close(record, DONE, now, reason))
        if state not in (FAILED, CANCELLED):
            raise TaskBufferError(f"instruction {instruction_id}: cannot close it as state "
                                  f"{state}")
        return self._close_chain(record, state, now, reason)

    def requeue(self, instruction_id: int) -> Record:
        """ACTIVE -> PENDING: the function was interrupted before it completed."""
        record = self._expect(instruction_id, (ACTIVE,), "requeue")
        return self._store(_replace(record, state=PENDING, started_time=0.0), durable=False)

    def _close_chain(self, record: Record, state: int, now: float, reason: str) -> Record:
        with self._db:  # one transaction: the instruction and its successors close together
            self._db.execute("BEGIN")
            closed = self._store(_close(record, state, now, reason))
            for successor, parent in self._open_successors(record.instruction.id):
                self._store(_close(successor, FAILED, now, f"predecessor {parent} "
                                                           f"{STATE_NAMES[self.get(parent).state]}"))
        return closed

    def fail_missing_predecessors(self, now: float) -> list[Record]:
        """Fail each open successor still waiting for a predecessor that has not arrived
        `predecessor_wait_s` after the successor was received; returns the failed records."""
        failed = []
        for instruction_id in list(self._awaiting):
            record = self._records[instruction_id]
            if not record.is_open or not self._missing_predecessor(record):
                del self._awaiting[instruction_id]
            elif now - record.received_time >= self.config.predecessor_wait_s:
                del self._awaiting[instruction_id]
                failed.append(self.fail(
                    instruction_id, now, f"predecessor {record.instruction.previous_id} never "
                    f"arrived ({self.config.predecessor_wait_s:g} s after instruction "
                    f"{instruction_id})"))
        return failed

    def _missing_predecessor(self, record: Record) -> bool:
        previous = record.instruction.previous_id
        return previous != 0 and previous not in self._records

    def _open_successors(self, instruction_id: int) -> list[tuple[Record, int]]:
        """[(open successor, its predecessor id)], breadth first down the chains."""
        found, frontier = [], [instruction_id]
        while frontier:
            parent = frontier.pop(0)
            for r in self.open_records():
                if r.instruction.previous_id == parent:
                    found.append((r, parent))
                    frontier.append(r.instruction.id)
        return found

    def _expect(self, instruction_id: int, states: Container[int], action: str) -> Record:
        record = self.get(instruction_id)
        if record.state not in states:
            raise TaskBufferError(f"instruction {instruction_id}: cannot {action} an instruction "
                                  f"that is {STATE_NAMES[record.state]}")
        return record

    def _store(self, record: Record, durable: bool = True) -> Record:
        """Write a state change (autocommit, or part of the caller's open transaction).

        `durable=False` commits without a disk sync: for ACTIVE <-> PENDING, which re-opening the
        journal undoes anyway (ACTIVE rows go back to PENDING), so losing such a write to a power
        cut leaves the journal exactly as a restart would read it. The next durable commit syncs
        the write-ahead log, these rows included. DONE, FAILED, CANCELLED and new instructions
        are always synced before the call returns.
        """
        write = self._db.execute if durable else self._lazy_write
        write("UPDATE instructions SET state=?, started_time=?, completion_time=?, "
              "reward_earned=?, reason=? WHERE id=?",
              (record.state, record.started_time, record.completion_time, record.reward_earned,
               record.reason, record.instruction.id))
        self._index(record)
        self.version += 1
        return record

    def _lazy_write(self, sql: str, values: tuple[Any, ...]) -> None:
        """Execute and commit `sql` without a disk sync (inside a caller's transaction: as is)."""
        lazy = not self._db.in_transaction and self.config.synchronous != "OFF"
        if lazy:
            self._db.execute("PRAGMA synchronous=OFF")
        try:
            self._db.execute(sql, values)
        finally:
            if lazy:
                self._db.execute(f"PRAGMA synchronous={self.config.synchronous}")

    def _index(self, record: Record) -> None:
        """Keep the in-memory views (all, open, done ids, the active id, recently finished ids,
        counts, reward, largest id) in step with the journal."""
        instruction = record.instruction
        instruction_id = instruction.id
        before = self._records.get(instruction_id)
        if before is not None:
            self._counts[before.state] -= 1
            self._total_reward -= before.reward_earned
        else:
            self._max_id = max(self._max_id, instruction_id, instruction.previous_id)
        self._counts[record.state] += 1
        self._total_reward += record.reward_earned
        self._records[instruction_id] = record
        if record.is_open:
            self._open[instruction_id] = record
        else:
            self._open.pop(instruction_id, None)
            if before is None or before.is_open:
                self._recent.append(instruction_id)   # the oldest drops out (maxlen)
        if record.state == ACTIVE:
            self._active = instruction_id
        elif self._active == instruction_id:
            self._active = 0
        if record.state == DONE:
            self._done.add(instruction_id)

    def _load(self) -> Iterator[Record]:
        for row in self._db.execute("SELECT * FROM instructions ORDER BY seq").fetchall():
            instruction, problem = self._loaded(row)
            if problem or instruction is None:   # no problem: an instruction
                self._quarantine(row, problem)
                continue
            yield Record(instruction, *row[14:21])

    def _loaded(self, row: tuple[Any, ...]) -> tuple[Instruction | None, str]:
        """(Instruction, "") of a journal row, or (None, why it does not load)."""
        problem = column_problem(row, STATE_NAMES)
        if problem:
            return None, problem
        try:
            instruction = Instruction(**dict(zip(_INSTRUCTION_FIELDS, _instruction_values(row))))
        except InvalidInstruction as error:
            return None, str(error)
        return instruction, self._refusal(instruction)

    def _quarantine(self, row: tuple[Any, ...], problem: str) -> None:
        """A journal row that does not load (written by an older version, by hand, or damaged)
        is failed with the reason and left out, so it is never run; its id stays used."""
        reason = f"quarantined: journal row {row[0]} is no valid instruction: {problem}"
        self.quarantined.append((row[0], reason))
        if row[14] in (PENDING, ACTIVE):
            received = row[15] if isinstance(row[15], int | float) else 0.0
            self._db.execute("UPDATE instructions SET state=?, completion_time=?, reason=? "
                             "WHERE id=?", (FAILED, received, reason, row[0]))


def _instruction_values(row: tuple[Any, ...]) -> list[Any]:
    """Journal column order -> Instruction field order."""
    by_column = dict(zip(("id", "previous_id", "gamma", "beta", "destination", "type",
                          "start_time", "duration", "source", "target", "status", "function",
                          "destination_name", "text"), row[:14]))
    return [by_column[name] for name in _INSTRUCTION_FIELDS]


def _row(record: Record) -> tuple[Any, ...]:
    i = record.instruction
    return (i.id, i.previous_id, i.gamma, i.beta, i.destination, i.type, i.start_time, i.duration,
            i.source, i.target, i.status, i.function, i.destination_name, i.text, record.state,
            record.received_time, record.started_time, record.completion_time,
            record.reward_earned, record.reason, record.seq)


def _replace(record: Record, **changes: Any) -> Record:
    values = {f.name: getattr(record, f.name) for f in fields(Record)}
    values.update(changes)
    return Record(**values)


def _close(record: Record, state: int, now: float, reason: str) -> Record:
    return _replace(record, state=state, completion_time=float(now), reason=reason)


def journalled_searches(db: sqlite3.Connection) -> list[JournalledSearch]:
    """Every search journalled in an open journal connection, oldest first, as (instruction_id,
    target, start_s, end_s, found, [place names]) tuples; none in a journal without the table."""
    try:
        rows = db.execute("SELECT instruction_id, target, start_s, end_s, found, places "
                          "FROM searches ORDER BY rowid").fetchall()
    except sqlite3.OperationalError:  # written before searches were journalled
        return []
    return [(i, target, start, end, bool(found), places.split(",") if places else [])
            for i, target, start, end, found, places in rows]
