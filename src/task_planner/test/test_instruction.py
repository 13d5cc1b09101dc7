import math
import re

import pytest

from task_planner.instruction import (BETA_MIN, DURATION_MAX_S, GAMMA_MAX, NAME_MAX_CHARS,
                                      ROBOT, TEXT_MAX_CHARS, Instruction, InvalidInstruction)


def make(**changes):
    fields = dict(id=1, gamma=8.0, beta=0.98, destination=2)
    fields.update(changes)
    return Instruction(**fields)


def test_valid_instruction_keeps_its_fields():
    instruction = make(previous_id=4, type=ROBOT, duration=30, text="check Bob")
    assert (instruction.previous_id, instruction.type, instruction.duration) == (4, ROBOT, 30)


def test_the_bounds_are_the_documented_values():
    assert (GAMMA_MAX, BETA_MIN, DURATION_MAX_S, TEXT_MAX_CHARS, NAME_MAX_CHARS) == \
        (100.0, 0.01, 3600, 1000, 100)


@pytest.mark.parametrize("changes", [
    dict(gamma=GAMMA_MAX), dict(beta=BETA_MIN), dict(duration=DURATION_MAX_S),
    dict(duration=600, function=8),  # charge, the longest configured function
    dict(text="x" * TEXT_MAX_CHARS), dict(text="[about Alice] " + "x" * 500),
    dict(source="s" * NAME_MAX_CHARS, target="t" * NAME_MAX_CHARS,
         destination_name="d" * NAME_MAX_CHARS),
])
def test_values_at_the_bounds_are_accepted(changes):
    assert make(**changes)


@pytest.mark.parametrize("changes, rule", [
    (dict(gamma=0.0), "gamma must lie in (0, 100] (Eq. 4-2); got gamma = 0.0"),
    (dict(gamma=-2.0), "gamma must lie in (0, 100]"),
    (dict(gamma=100.5), "gamma must lie in (0, 100] (Eq. 4-2); got gamma = 100.5"),
    (dict(gamma=math.inf), "gamma must be a finite number; got gamma = inf"),
    (dict(gamma=math.nan), "gamma must be a finite number; got gamma = nan"),
    (dict(beta=1.0), "beta must lie in [0.01, 1)"),
    (dict(beta=0.0), "beta must lie in [0.01, 1)"),
    (dict(beta=1.0e-300), "beta must lie in [0.01, 1) (Eq. 4-2); got beta = 1e-300"),
    (dict(beta=math.nan), "beta must lie in [0.01, 1)"),
    (dict(id=0), "id must be > 0"),
    (dict(previous_id=1), "previous_id must differ from id"),
    (dict(duration=-1), "duration must lie in 0..3600 s; got duration = -1"),
    (dict(duration=2 ** 31 - 1), "duration must lie in 0..3600 s; got duration = 2147483647"),
    (dict(type=2), "type must be 0 (human) or 1 (robot)"),
    (dict(start_time=math.inf), "start_time must be a finite number; got start_time = inf"),
    (dict(start_time=-1.0), "start_time must be >= 0 s"),
    (dict(text="x" * 2 ** 20),
     "text must be at most 1000 characters; got text = 1048576 characters"),
    (dict(source="s" * 101), "source must be at most 100 characters; got source = 101 char"),
    (dict(target="t" * 101), "target must be at most 100 characters"),
    (dict(destination_name="k" * 101), "destination_name must be at most 100 characters"),
])
def test_invalid_instruction_names_the_instruction_and_the_broken_rule(changes, rule):
    named = re.escape(f"instruction {changes.get('id', 1)}: ") + ".*" + re.escape(rule)
    with pytest.raises(InvalidInstruction, match=named) as refused:
        make(**changes)
    assert len(str(refused.value)) < 200  # a refused 1 MB text is not repeated in the reason


def test_the_issue_poison_instruction_is_refused():
    """Issue 35: gamma inf, beta 1e-300 was accepted and its reward came out NaN."""
    with pytest.raises(InvalidInstruction, match="instruction 1: gamma must be a finite number"):
        Instruction(id=1, gamma=math.inf, beta=1.0e-300, destination=0, function=3,
                    duration=2, start_time=0.0)
