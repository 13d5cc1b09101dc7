"""The one list of instruction classes (Table 3.1-1) and the tables derived from it."""
import dataclasses

import pytest

from penguin_base.record_format import NUM_CLASSES as RECORD_CLASSES
from semantic_nav.instruction_classes import (BACK, CLASS_IDS, CLASSES, COUNTING_IDS, END_TURN,
                                              MAX_CORNER, MIRRORED_CLASS, NAMES, NUM_CLASSES,
                                              SIDE, STRAIGHT, TURN, TURN_AT, TURN_CLASSES,
                                              check_classes, get, ids)


def test_table_3_1_1():
    assert CLASS_IDS == (1, 2, 3, 4, 5, 6, 7, 8, 9, 10) and NUM_CLASSES == 10
    assert NAMES[1] == "go straight to the end" and NAMES[4] == "go back (turn around)"
    assert NAMES[8] == "turn left at the third corner"
    assert NAMES[9] == "go straight to the end and turn right"
    assert ids(motion=STRAIGHT) == (1,) and ids(motion=BACK) == (4,)
    assert SIDE == {2: "right", 3: "left", 5: "right", 6: "left", 7: "right", 8: "left",
                    9: "right", 10: "left"}
    assert {c.number: c.at for c in CLASSES if c.at} == {
        5: "second", 6: "second", 7: "third", 8: "third", 9: "end", 10: "end"}
    assert TURN_CLASSES == {("right", None): 2, ("left", None): 3, ("right", "second"): 5,
                            ("left", "second"): 6, ("right", "third"): 7, ("left", "third"): 8,
                            ("right", "end"): 9, ("left", "end"): 10}
    assert TURN_AT == ("second", "third", "end")


def test_derived_tables():
    assert MIRRORED_CLASS == {1: 1, 2: 3, 3: 2, 4: 4, 5: 6, 6: 5, 7: 8, 8: 7, 9: 10, 10: 9}
    assert END_TURN == {2: 9, 3: 10, 5: 9, 6: 10, 7: 9, 8: 10}
    assert COUNTING_IDS == (5, 6, 7, 8) and [get(c).corner for c in COUNTING_IDS] == [2, 2, 3, 3]
    assert MAX_CORNER == 3
    assert ids(motion=TURN, at=None) == (2, 3)
    assert {c.phrase_set for c in CLASSES} == {"class1", "class4", "class_turn"}


def test_penguin_base_records_the_same_classes():
    """penguin_base (record format, teleop keys) keeps its own count: it must match the list."""
    assert RECORD_CLASSES == NUM_CLASSES


def test_unknown_class_is_named():
    with pytest.raises(ValueError, match="unknown instruction class 11 \\(1..10\\)"):
        get(11)


@pytest.mark.parametrize("change, message", [
    (lambda cs: cs[:4] + cs[5:], "numbered 1..9 in order"),
    (lambda cs: [dataclasses.replace(cs[0], mirror=4)] + cs[1:], "mirror 4"),
    (lambda cs: cs[:1] + [dataclasses.replace(cs[1], mirror=6)] + cs[2:], "mirror 6"),
    (lambda cs: cs[:2] + [dataclasses.replace(cs[2], side="right", mirror=3)] + cs[3:],
     "mirror 3"),
    (lambda cs: cs[:4] + [dataclasses.replace(cs[4], at="fourth")] + cs[5:], "unknown `at`"),
    (lambda cs: [dataclasses.replace(cs[0], side="left")] + cs[1:], "side"),
])
def test_a_contradictory_list_is_refused(change, message):
    with pytest.raises(ValueError, match=message):
        check_classes(change(list(CLASSES)))
