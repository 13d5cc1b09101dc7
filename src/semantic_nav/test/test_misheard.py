"""Misheard words (semantic_nav.misheard) and the follower's rereading of them."""
import pytest

from semantic_nav.misheard import (MAX_READINGS, edit_distance, read_as, readings,
                                   reads_homophones, sound_alikes)


@pytest.mark.parametrize("a, b, distance", [
    ("lift", "left", 1), ("light", "right", 1), ("kitten", "sitting", 3), ("", "abc", 3),
    ("end", "end", 0), ("corner", "corners", 1), ("halt", "hold", 2)])
def test_edit_distance_counts_letter_edits_both_ways(a, b, distance):
    assert edit_distance(a, b) == distance
    assert edit_distance(b, a) == distance


def test_sound_alikes_are_the_vocabulary_words_within_the_edits_nearest_first():
    vocabulary = {"left", "lift", "lifts", "right", "loft", "at", "leftist"}
    assert sound_alikes("lift", vocabulary) == ["left", "lifts", "loft"]      # not itself
    assert sound_alikes("lift", vocabulary, max_edits=2) == ["left", "lifts", "loft"]
    assert sound_alikes("light", vocabulary, max_edits=2) == ["right", "lift"]
    assert sound_alikes("as", vocabulary) == []        # too short to tell
    assert sound_alikes("lift", vocabulary, max_edits=0) == []


def test_a_homophone_comes_before_the_words_a_letter_edit_away():
    vocabulary = {"right", "white", "writ", "left"}
    assert sound_alikes("write", vocabulary) == ["right", "white", "writ"]
    assert sound_alikes("write", vocabulary, max_edits=0) == []
    assert sound_alikes("write", {"left"}) == []      # its homophone is not a phrase word


def test_a_reading_reads_homophones_when_each_word_with_one_is_read_as_it():
    skipped = ["ride", "lift"]
    assert reads_homophones([("ride", "right")], skipped)
    assert reads_homophones([("ride", "right"), ("lift", "left")], skipped)   # and more
    assert not reads_homophones([("ride", "side"), ("lift", "left")], skipped)
    assert not reads_homophones([("lift", "left")], skipped)                 # "ride" unread
    assert reads_homophones([("lift", "loft")], ["lift"])                    # none has one


def test_readings_replace_skipped_words_in_every_combination():
    tokens = ["take", "a", "lift", "at", "the", "lader", "zzz"]
    found = readings(tokens, ["lift", "lader", "zzz"], {"left", "loft", "later"})
    assert [fixed for _, fixed in found] == [
        (("lift", "left"),), (("lift", "loft"),), (("lader", "later"),),
        (("lift", "left"), ("lader", "later")), (("lift", "loft"), ("lader", "later"))]
    assert found[0][0] == ["take", "a", "left", "at", "the", "lader", "zzz"]   # zzz: no alike
    assert readings(tokens, ["zzz"], {"left"}) == []
    many = readings([f"w{i}x" for i in range(8)], [f"w{i}x" for i in range(8)],
                    {f"w{i}y" for i in range(8)} | {f"w{i}z" for i in range(8)})
    assert len(many) == MAX_READINGS
    assert all(len(fixed) == 1 for _, fixed in many[:16])   # every single replacement first


def test_read_as_says_what_was_read_as_what():
    assert read_as([("lift", "left"), ("light", "right")]) == "'lift' as 'left', 'light' as 'right'"
    assert read_as([]) == ""
