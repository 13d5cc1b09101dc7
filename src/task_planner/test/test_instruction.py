import pytest

from task_planner.instruction import ROBOT, Instruction, InvalidInstruction


def make(**changes):
    fields = dict(id=1, gamma=8.0, beta=0.98, destination=2)
    fields.update(changes)
    return Instruction(**fields)


def test_valid_instruction_keeps_its_fields():
    instruction = make(previous_id=4, type=ROBOT, duration=30, text="check Bob")
    assert (instruction.previous_id, instruction.type, instruction.duration) == (4, ROBOT, 30)


@pytest.mark.parametrize("changes, rule", [
    (dict(gamma=0.0), "gamma must be > 0"),
    (dict(gamma=-2.0), "gamma must be > 0"),
    (dict(beta=1.0), "beta must lie in (0, 1)"),
    (dict(beta=0.0), "beta must lie in (0, 1)"),
    (dict(id=0), "id must be > 0"),
    (dict(previous_id=1), "previous_id must differ from id"),
    (dict(duration=-1), "duration must be >= 0"),
    (dict(type=2), "type must be 0 (human) or 1 (robot)"),
])
def test_invalid_instruction_names_the_broken_rule(changes, rule):
    with pytest.raises(InvalidInstruction, match=rule.replace("(", r"\(").replace(")", r"\)")):
        make(**changes)
