"""Handing instructions to the task buffer, which allocates their ids.

A sender does not choose ids: it submits each instruction with id 0 on /task_planner/submit and
the task buffer answers with the id it journalled it under (one more than any id it ever
journalled; TaskBuffer.next_id). Until then an instruction carries a provisional id: 1, 2, ... in
chain order, a successor's `previous_id` naming its predecessor's provisional id (0 = none).
`submit_chain` submits a chain in order, the successor with the id allocated for its
predecessor, and stops at the first refusal: a successor of an instruction the buffer did not take
would only wait for a predecessor that never comes.
"""
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace

from task_planner.instruction import Instruction


@dataclass(frozen=True)
class Submission:
    accepted: tuple[Instruction, ...]  # the accepted Instructions with their allocated ids, in
    #                                    chain order
    refusal: str = ""   # why the task planner did not take the next one; "" = all accepted
    not_sent: int = 0   # instructions of the chain not submitted after the refusal

    @property
    def complete(self) -> bool:
        return not self.refusal


def submit_chain(instructions: Sequence[Instruction],
                 submit: Callable[[Instruction, int], tuple[bool, int, str]]) -> Submission:
    """Submit a chain (provisional ids, see above) in order; returns a Submission.

    Args:
        instructions: Instructions in chain order.
        submit: callable(instruction, previous_id) -> (accepted, id, message): one request with
            id 0 and `previous_id` (the id allocated for the predecessor; 0 = none), answered
            with the allocated id or the reason of a refusal.
    Raises ValueError for a `previous_id` that names no earlier instruction of the chain.
    """
    allocated: dict[int, int] = {}
    accepted: list[Instruction] = []
    for k, instruction in enumerate(instructions):
        provisional = instruction.previous_id
        if provisional and provisional not in allocated:
            raise ValueError(f"provisional instruction {instruction.id}: previous_id "
                             f"{provisional} is no earlier instruction of the chain")
        previous = allocated.get(provisional, 0)
        ok, instruction_id, message = submit(instruction, previous)
        if not ok:
            return Submission(tuple(accepted), message or "refused without a reason",
                              len(instructions) - k)
        allocated[instruction.id] = instruction_id
        accepted.append(replace(instruction, id=instruction_id, previous_id=previous))
    return Submission(tuple(accepted))
