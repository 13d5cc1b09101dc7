"""Decoding held to a command vocabulary: the words, the tokens barred, the reading taken."""
import math
from types import SimpleNamespace

import pytest

from perception.stt_vocabulary import (PUNCTUATION, Decoding, VocabularyError, choose_reading,
                                       suppressed_outside, vocabulary_path, vocabulary_words,
                                       window_log_prob)


def test_a_yaml_vocabulary_is_the_words_of_its_string_values(tmp_path):
    """Mapping keys, comments and {placeholders} name no word; another file is all words."""
    path = tmp_path / "phrases.yaml"
    path.write_text("# the classifier's phrases\nclass1:\n  train: [Go straight, \"don't stop!\"]\n"
                    "  held_out: [\"turn {dir} at the 2nd corner\", \"pass two {dir}s\"]\n")
    assert vocabulary_words(path) == {"go", "straight", "don't", "stop", "turn", "at", "the",
                                      "nd", "corner", "pass", "two", "s"}   # "s" of "{dir}s"
    words = tmp_path / "words.txt"
    words.write_text("# left and right\nturn")
    assert vocabulary_words(words) == {"left", "and", "right", "turn"}


def test_a_vocabulary_that_cannot_be_read_or_has_no_word_is_named(tmp_path):
    with pytest.raises(VocabularyError, match="missing.txt"):
        vocabulary_words(tmp_path / "missing.txt")
    (tmp_path / "bad.yaml").write_text("turn: [left\n")
    with pytest.raises(VocabularyError, match="bad.yaml"):
        vocabulary_words(tmp_path / "bad.yaml")
    (tmp_path / "digits.txt").write_text("1 2 3\n")
    with pytest.raises(VocabularyError, match="digits.txt holds no word"):
        vocabulary_words(tmp_path / "digits.txt")


def test_a_relative_vocabulary_is_in_the_config_folder(tmp_path):
    assert vocabulary_path("semnav_phrases.yaml", tmp_path) == tmp_path / "semnav_phrases.yaml"
    assert vocabulary_path("/etc/words.txt", tmp_path).as_posix() == "/etc/words.txt"
    assert vocabulary_path("~/words.txt", tmp_path).is_absolute()


def test_every_token_but_the_words_forms_and_punctuation_is_barred():
    pieces = {" left": [1], "left": [2], " Left": [3], "Left": [2, 4], " two": [5], "two": [5],
              " Two": [6], "Two": [7]}
    pieces.update({mark: [8] for mark in PUNCTUATION})
    barred = suppressed_outside(lambda text: pieces[text], 12, {"left", "two"})
    assert barred == [0, 9, 10, 11]
    assert suppressed_outside(lambda text: pieces[text], 12, {"left", "two"}, (8, 4)) == \
        [0, 4, 8, 9, 10, 11]     # Whisper's non-speech tokens stay barred


def test_a_windows_log_prob_is_counted_once_over_its_segments():
    """faster-whisper gives every segment cut from one window the window's avg_logprob: the
    sum over its 37 tokens and its end, divided by 38."""
    def segment(seek, tokens, average):
        return SimpleNamespace(seek=seek, tokens=[0] * tokens, avg_logprob=average)
    assert window_log_prob([segment(0, 24, -0.5), segment(0, 13, -0.5)]) == -19.0
    assert window_log_prob([segment(0, 9, -0.5), segment(3000, 4, -1.0)]) == -10.0
    assert window_log_prob([]) == 0


@pytest.mark.parametrize("held, margin, expected", [
    (Decoding("take the third left", -4.0), 2.0, ("take the third left", True)),
    (Decoding("take the third left", -5.0), 2.0, ("take the third left", True)),   # at the margin
    (Decoding("take the third left", -5.1), 2.0, ("take the dog left", False)),
    (Decoding("take the third left", -5.1), 3.0, ("take the third left", True)),
    (None, 2.0, ("take the dog left", False)),            # the held decoding looped
    (Decoding("", 0.0), 2.0, ("take the dog left", False))])
def test_the_held_reading_is_taken_within_the_margin(held, margin, expected):
    assert choose_reading(Decoding("take the dog left", -3.0), held, margin) == expected


@pytest.mark.parametrize("margin", [-0.1, math.inf, math.nan])
def test_a_margin_that_is_no_distance_is_refused(margin):
    with pytest.raises(ValueError, match="margin must be a finite number >= 0"):
        choose_reading(Decoding("a", 0.0), None, margin)
