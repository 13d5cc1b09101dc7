"""Instruction layer (thesis 002 §2.2.3, §3.1) on the seed's example sentences."""
import numpy as np
import pytest

from semantic_nav.instruction_layer import (InstructionError, convert_instruction,
                                            sentence_vector, split_instruction, tokenise)
from semantic_nav.word_vectors import WordVectors


def test_split_seed_example_of_section_3_1():
    assert split_instruction("Turn right, and then go straight to the end of the aisle.") == [
        "turn right", "go straight to the end of the aisle"]


def test_split_seed_examples_of_section_1_1():
    assert split_instruction("Go straight to the end, turn right, and then enter the second "
                             "room on your left hand side.") == [
        "go straight to the end", "turn right",
        "enter the second room on your left hand side"]
    assert split_instruction("You just turn right at the end of this aisle, and then turn left "
                             "at the second entry.") == [
        "you just turn right at the end of this aisle", "turn left at the second entry"]


def test_split_spoken_text_without_punctuation():
    assert split_instruction("go straight to the end then turn left and then go back") == [
        "go straight to the end", "turn left", "go back"]


def test_and_alone_does_not_split():
    assert split_instruction("Go straight to the end and turn right") == [
        "go straight to the end and turn right"]
    assert split_instruction("turn left at the corner and stop, please") == [
        "turn left at the corner and stop", "please"]


def test_empty_sentence_is_a_clear_error():
    for text in ["", "   ", ", . ! ?", "and then"]:
        with pytest.raises(InstructionError, match="has no words"):
            split_instruction(text)
    with pytest.raises(InstructionError, match="must be text"):
        split_instruction(None)


def test_tokenise_lower_case_and_clitics():
    assert tokenise("I'd like you to Turn RIGHT at the 2nd corner") == [
        "i", "'d", "like", "you", "to", "turn", "right", "at", "the", "second", "corner"]
    assert tokenise("don't make a u-turn") == ["do", "n't", "make", "a", "u-turn"]


def test_numerals_become_the_words_of_the_phrase_sets():
    assert tokenise("turn left 2 corners down") == ["turn", "left", "two", "corners", "down"]
    assert tokenise("at the 1st, 3rd or 10th corner, 0 or 10") == [
        "at", "the", "first", "third", "or", "tenth", "corner", "zero", "or", "ten"]
    # beyond ten, and digits inside other words, stay as they are (GloVe has them)
    assert tokenise("room 101 on the 11th floor, b2 wing") == [
        "room", "101", "on", "the", "11th", "floor", "b2", "wing"]


@pytest.fixture
def tiny_vectors():
    words = ["turn", "right", "go", "back"]
    return WordVectors(words, np.arange(8, dtype=np.float32).reshape(4, 2), "tiny")


def test_oov_words_are_skipped_and_counted(tiny_vectors):
    result = sentence_vector("turn right quickly", tiny_vectors)
    assert result.tokens == ["turn", "right", "quickly"]
    assert result.oov == ["quickly"]
    np.testing.assert_array_equal(result.vectors, [[0, 1], [2, 3]])
    sentence_vector("quickly go back", tiny_vectors)
    assert tiny_vectors.oov_counts == {"quickly": 2}


def test_sentence_of_only_unknown_words_is_a_clear_error(tiny_vectors):
    with pytest.raises(InstructionError, match="unknown: zorp, blig"):
        sentence_vector("Zorp blig!", tiny_vectors)


def test_convert_instruction_keeps_order(tiny_vectors):
    parts = convert_instruction("Turn right, then go back.", tiny_vectors)
    assert [p.text for p in parts] == ["turn right", "go back"]
    np.testing.assert_array_equal(parts[1].vectors, [[4, 5], [6, 7]])
