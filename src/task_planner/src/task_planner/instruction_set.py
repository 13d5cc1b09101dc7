"""A set of instructions ready for planning: validation and chains through `previous_id`.

A successor becomes eligible only once its predecessor is done (Table 4-1 note on
`previous_id`). A `previous_id` that names no instruction of the set is taken as already done (the
task buffer drops finished instructions).
"""
from collections.abc import Container, Sequence

from task_planner.instruction import Instruction, InvalidInstruction


def validate_instruction_set(instructions: Sequence[Instruction], node_count: int) -> None:
    """Raise InvalidInstruction naming the first bad item: duplicate id, unknown node, or cycle."""
    seen = set()
    for instruction in instructions:
        if instruction.id in seen:
            raise InvalidInstruction(f"instruction {instruction.id}: duplicate id in the set")
        seen.add(instruction.id)
        if not 0 <= instruction.destination < node_count:
            raise InvalidInstruction(
                f"instruction {instruction.id}: destination node {instruction.destination} is not "
                f"in the graph (nodes 0..{node_count - 1})")
    check_chains_acyclic(instructions)


def check_chains_acyclic(instructions: Sequence[Instruction]) -> None:
    """Raise InvalidInstruction if following `previous_id` ever returns to an instruction."""
    previous = {i.id: i.previous_id for i in instructions}
    for start in previous:
        chain = [start]
        current = previous[start]
        while current in previous:
            if current in chain:
                cycle = " -> ".join(str(i) for i in chain[chain.index(current):] + [current])
                raise InvalidInstruction(f"previous_id forms a cycle: {cycle}")
            chain.append(current)
            current = previous[current]


def eligible(instruction: Instruction, pending_ids: Container[int]) -> bool:
    """True when the instruction's predecessor is no longer pending (done or never in the set)."""
    return instruction.previous_id == 0 or instruction.previous_id not in pending_ids
