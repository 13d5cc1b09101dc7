"""Blind sets of directions: loading (errors name file and entry), scoring, wrong sides."""
import re

import pytest
from tamp_resources import resource

from semnav_learning.blind_set import (BlindSetError, format_blind_score, load_blind_set,
                                       score_blind_set, turned_back, wrong_side)


def write(tmp_path, text):
    path = tmp_path / "blind.yaml"
    path.write_text(text)
    return path


BLIND_SETS = ("semnav_blind_directions.yaml", "semnav_blind_directions_2.yaml")


@pytest.mark.parametrize("name", BLIND_SETS)
def test_the_committed_blind_sets_cover_every_class_and_both_counting_modes(name):
    entries = load_blind_set(resource("config", name))
    assert len(entries) >= 150
    singles = {e.classes[0] for e in entries if len(e.classes) == 1}
    assert singles == set(range(1, 11))
    assert {"corner", "side"} <= {mode for e in entries for mode in e.count}


def test_the_second_blind_set_shares_no_sentence_with_the_first():
    first, second = ({e.text for e in load_blind_set(resource("config", name))}
                     for name in BLIND_SETS)
    assert not first & second


@pytest.mark.parametrize("text, message", [
    ("entries: [{text: go, classes: [11]}]", "entries[0].classes: expected a list of class"),
    ("entries: [{text: go, classes: [1], count: [sides]}]", "entries[0].count"),
    ("entries: [{text: go, classes: [1], colour: red}]", "unknown key 'colour'"),
    ("entries: [{text: go, classes: [1]}, {text: go, classes: [1]}]", "listed twice"),
    ("[1, 2]", "a list `entries`"),
])
def test_bad_entries_are_named(tmp_path, text, message):
    with pytest.raises(BlindSetError, match=re.escape(message)):
        load_blind_set(write(tmp_path, text))


def test_wrong_side_is_a_turn_read_to_the_other_side():
    assert wrong_side((5,), (6,)) and wrong_side((9,), (3,))
    assert not wrong_side((5,), (2,))          # same side, wrong corner: a miss, not a side
    assert not wrong_side((1,), (3,)) and not wrong_side((2, 1), (2, 4))


def test_a_turn_around_read_for_a_straight_or_first_turn_is_counted():
    assert turned_back([(1,)], [4]) and turned_back([(2, 1)], [2, 4])
    assert turned_back([(10,), (1, 3)], [4, 3])
    assert not turned_back([(4, 1)], [4, 1])           # a turn around was meant
    assert not turned_back([(5,)], [4])                # no class 1-3 direction meant
    assert not turned_back([(1,)], [1]) and not turned_back([(1,)], None)


def test_scoring_accepts_either_reading_and_counts_refusals_as_misses(tmp_path):
    entries = load_blind_set(write(tmp_path, """
entries:
  - {text: "at the end, go left", classes: [10], or: [1, 3]}
  - {text: "take the second right", classes: [5], count: [side]}
  - {text: "blorp", classes: [1]}
  - {text: "two corners on, go left", classes: [6]}
"""))
    answers = {"at the end, go left": [1, 3], "take the second right": [5],
               "two corners on, go left": [5, 3]}

    def classify(text):
        if text not in answers:
            raise ValueError("no known word")
        return answers[text]

    score = score_blind_set(entries, classify)
    assert score.accuracy == 0.5
    assert [r[0].text for r in score.wrong_sides] == ["two corners on, go left"]
    assert score.per_group() == {10: [1, 1], 5: [1, 1], 1: [0, 1], 6: [0, 1]}
    lines = format_blind_score(score)
    assert lines[0] == ("blind set: 2/4 = 50.00% read as meant; 1 to the wrong side; 0 class 1-3 "
                        "directions read as a turn around")
    assert "'blorp': meant 1, read refused (no known word)" in lines[2]
    assert lines[3].endswith("read 5 3  WRONG SIDE")
