"""One executor's part in a fleet, ROS-free: its own task buffer linked to the pool all share.

Thesis 000 ends (Ch. 6) with robots that share the instructions of one home. Each executor keeps
its own journal (task_buffer); the pool (fleet_pool) is what the robots agree on:
- what a robot receives it shares, and it takes in what the others received (`news`), so every
  journal holds every instruction of the fleet; ids left to the fleet come from the pool's one
  counter (`next_id`);
- the robot chooses among the instructions no other robot holds (`taken`) with the fleet's
  auction over the robots' reports of where and when they will be free (`report`, `fleet`;
  behaviours.fleet_allocation), or with its own planner alone (fleet_registry `seed`,
  `rollout`), and claims its choice before it drives for it (`claim`). A robot holds one claim
  at a time: claiming another gives the previous one back;
- while it works it renews its lease (`renew`, every `renew_period_s`); a robot that dies stops
  renewing, and its instruction returns to the others once the lease has run out;
- before it drives into a corridor it holds it (`enter`), and it gives it up once it stands
  outside (`leave`): one robot at a time in a narrow place; the other waits;
- what it finishes, fails or is told to cancel it closes in the pool; what the pool holds closed
  it closes in its own journal (`closed_in_pool`);
- at its first event, after a fault and after a failed pool write it `rejoin`s from its
  journal: it closes in the pool what its journal closed, gives back the claims and corridors
  it held but claims again what it serves on, and shares what it journalled but the pool
  lacks.
Instructions the robot gives itself for its own body (charging) are `keep_local`: never shared
and never claimed.
"""
from collections.abc import Callable, Collection, Iterable
from contextlib import AbstractContextManager

from task_planner.fleet_pool import (CANCELLED, CLAIMED, DONE, FAILED, OPEN, STATE_NAMES,
                                     FleetPool, LeaseLost)
from task_planner import task_buffer
from task_planner.instruction import Instruction
from task_planner.task_buffer import Record

# pool state -> the task buffer state an instruction closed elsewhere takes
_BUFFER_STATE = {DONE: task_buffer.DONE, FAILED: task_buffer.FAILED,
                 CANCELLED: task_buffer.CANCELLED}
_POOL_STATE = {buffer_state: pool_state for pool_state, buffer_state in _BUFFER_STATE.items()}


class FleetLink:
    """The pool as one robot named `robot` sees it (the name is the pool's claim holder)."""

    def __init__(self, pool: FleetPool, robot: str, renew_period_s: float | None = None) -> None:
        self.pool, self.robot = pool, robot
        # renew well within the lease: three chances before it runs out
        self.renew_period_s = pool.lease_s / 3 if renew_period_s is None else renew_period_s
        self.held = 0              # the instruction id this robot holds (0: none)
        self.local: set[int] = set()       # ids of instructions kept to this robot
        self.corridors: set[str] = set()   # names of the corridors this robot holds
        self._place = -1           # where the robot serves the one it holds
        self._seq = 0              # the pool's last shared instruction taken in
        self._renewed_at = -float("inf")
        self._reported: tuple[tuple[int, float], float] | None = None  # ((node, free_at),
                                   # when) of the last report

    def rejoin(self, records: Iterable[Record], own: Callable[[Instruction], bool], keep: int = 0,
               now: float = 0.0, place: int = -1) -> dict[int, str]:
        """Start from the journal's `records`, in one pool transaction: close in the pool what
        the journal closed (when the pool holds that instruction under its id), give back every
        claim and corridor held before, claim again `keep` (the instruction the robot serves
        on, at `place`), keep local the open ones `own(instruction)` says are the robot's own
        and the pool lacks, and share the other open ones. Returns {id: reason} of the open
        ones the pool holds another instruction under: the robot must not serve them (the
        fleet knows that id as another's), and does not hold `keep` if it is one of them."""
        with self.pool.transaction():
            entries = {entry.id: entry for entry in self.pool.entries()}
            unshared: list[Instruction] = []
            closed: list[Record] = []
            for record in records:
                instruction, entry = record.instruction, entries.get(record.instruction.id)
                if not record.is_open:
                    if entry is not None and entry.state in (OPEN, CLAIMED):
                        closed.append(record)
                elif instruction.id in self.local or (entry is None and own(instruction)):
                    self.local.add(instruction.id)
                else:
                    unshared.append(instruction)
            theirs = self.pool.conflicting([record.instruction for record in closed])
            for record in closed:
                if record.instruction.id not in theirs:
                    self.pool.settle(self.robot, record.instruction.id, record.completion_time,
                                     _POOL_STATE[record.state])
            clashes = self.pool.conflicting(unshared)
            self.share([i for i in unshared if i.id not in clashes])
            self.pool.release_all(self.robot)
            self.held, self._place, self.corridors = 0, -1, set()
            if keep and keep not in self.local and keep not in clashes and self.pool.claim(
                    self.robot, keep, now, place):
                self.held, self._place, self._renewed_at = keep, place, now
        return clashes

    def next_id(self, above: int = 0) -> int:
        """An id no robot of the fleet has used, above `above` (the robot's own journal's)."""
        return self.pool.next_id(above)

    def keep_local(self, instruction_id: int) -> None:
        self.local.add(int(instruction_id))

    def conflicts(self, instructions: Iterable[Instruction]) -> dict[int, str]:
        """{id: reason} of the instructions whose id the pool holds for another instruction."""
        return self.pool.conflicting([i for i in instructions if i.id not in self.local])

    def transaction(self) -> AbstractContextManager[None]:
        """The pool's transaction context (FleetPool.transaction)."""
        return self.pool.transaction()

    def share(self, instructions: Iterable[Instruction]) -> dict[int, str]:
        """Share instructions this robot accepted; {id: reason} of those the pool refused."""
        return self.pool.share([i for i in instructions if i.id not in self.local])

    def news(self) -> list[Instruction]:
        """Instructions the other robots shared since the last call, in their order."""
        self._seq, shared = self.pool.since(self._seq)
        return shared

    def taken(self, now: float) -> set[int]:
        """Ids this robot must not choose at `now`: held by another robot."""
        return self.pool.held_by_others(self.robot, now)

    def busy_places(self, now: float) -> set[int]:
        """Places where another robot serves, or drives to serve, what it holds."""
        return self.pool.places_held_by_others(self.robot, now)

    def closed_in_pool(self, ids: Iterable[int]) -> list[tuple[int, int, str]]:
        """[(id, task buffer state, reason)] of `ids` the pool holds closed: by another robot,
        or by this one before its journal was lost."""
        return [(i, _BUFFER_STATE[entry.state], f"{STATE_NAMES[entry.state]} by {entry.robot}")
                for i, entry in self.pool.closed([i for i in ids if i not in self.local]).items()]

    def claim(self, instruction_id: int, now: float, place: int = -1) -> bool:
        """True when the robot holds the instruction now (kept ones always), to serve it at
        `place`; gives back the one it held before."""
        if instruction_id in self.local:
            self.release()   # it serves its own body now
            return True
        if instruction_id == self.held and place == self._place:
            return True   # a held one is renewed by `renew`; `holds` checks it before serving
        if not self.pool.claim(self.robot, instruction_id, now, place):
            return False
        if self.held and self.held != instruction_id:
            self.pool.release(self.robot, self.held)
        self.held, self._place, self._renewed_at = instruction_id, place, now
        return True

    def holds(self, instruction_id: int, now: float) -> bool:
        """True when the robot still holds the instruction at `now` (renewing its lease)."""
        if instruction_id in self.local:
            return True
        self._renewed_at = now
        if self.pool.renew(self.robot, now, [instruction_id], self.corridors):
            return True
        if self.held == instruction_id:
            self.held = 0
        return False

    def enter(self, names: Collection[str], now: float) -> str:
        """Hold the corridors `names` (keeping those held); "" or the robot in one of them."""
        holder = self.pool.enter(self.robot, sorted(names), now)
        if not holder:
            self.corridors |= set(names)
        return holder

    def leave(self, keep: Iterable[str] = ()) -> None:
        """Give up the corridors held but those in `keep` (in the pool too, whatever this link
        remembers)."""
        kept = tuple(keep)
        self.pool.leave(self.robot, kept)
        self.corridors &= set(kept)

    def renew(self, now: float) -> None:
        """Renew the robot's lease when `renew_period_s` has passed since the last renewal."""
        if (self.held or self.corridors) and now - self._renewed_at >= self.renew_period_s:
            self._renewed_at = now
            ids = [self.held] if self.held else []
            if not self.pool.renew(self.robot, now, ids, self.corridors):
                self.held = 0   # lost: another robot may hold it now (closed_in_pool tells)

    def report(self, node: int, free_at: float, now: float) -> None:
        """Tell the fleet where this robot will be free next and from when [s]: when that
        changed, and within its lease otherwise (renew_period_s)."""
        state = (int(node), round(float(free_at), 3))
        if self._reported is not None and self._reported[0] == state and \
                now - self._reported[1] < self.renew_period_s:
            return
        self.pool.report(self.robot, state[0], state[1], now)
        self._reported = (state, now)

    def fleet(self, now: float) -> dict[str, tuple[int, float]]:
        """{robot: (node, free_at)} of the fleet's robots that reported within their lease."""
        return self.pool.robots(now)

    def release(self) -> None:
        """Give back the instruction the robot holds (it serves none now)."""
        if self.held:
            self.pool.release(self.robot, self.held)
            self.held = 0

    def close(self, instruction_id: int, now: float, state: int) -> str:

        """Close an instruction this robot finished (DONE) or failed (FAILED) in the pool, or one
        it was told to cancel (CANCELLED). Returns "" or why the pool did not take it (the
        robot's lease ran out: another robot may have served it too)."""
        instruction_id = int(instruction_id)
        if instruction_id in self.local:
            return ""
        if self.held == instruction_id:
            self.held = 0
        if state == CANCELLED:
            self.pool.cancel(self.robot, instruction_id, now)
            return ""
        try:
            (self.pool.complete if state == DONE else self.pool.fail)(
                self.robot, instruction_id, now)
        except LeaseLost as error:
            return str(error)
        return ""
