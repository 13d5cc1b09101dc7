"""Splitting a sentence into simple instructions (thesis 002 §3.1; "spoken" beyond the seed)."""
import pytest

from semantic_nav.splitting import InstructionError, split_instruction


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
    assert split_instruction("turn left at the corner and stop, please", "seed") == [
        "turn left at the corner and stop", "please"]


def test_spoken_splitting_ends_instructions_at_connectives():
    assert split_instruction("turn right and after that go back") == ["turn right", "go back"]
    assert split_instruction("take a left, once you're there go straight to the end") == [
        "take a left", "go straight to the end"]
    assert split_instruction("go to the end and turn right once you are there") == [
        "go to the end and turn right"]


def test_spoken_splitting_joins_pieces_that_name_no_motion():
    assert split_instruction("Hey robot, hang a left") == ["hey robot hang a left"]
    assert split_instruction("at the second corner, turn left") == [
        "at the second corner turn left"]
    assert split_instruction("turn left at the corner and stop, please") == [
        "turn left at the corner and stop please"]
    assert split_instruction("turn around. um, ok. go to the end") == [
        "turn around", "um ok go to the end"]
    assert split_instruction("thanks, please") == ["thanks please"]    # nothing to join to


def test_spoken_splitting_joins_a_lead_in_to_the_turn_after_it():
    assert split_instruction("go past two corners and then turn left") == [
        "go past two corners turn left"]
    assert split_instruction("go straight, then take the second right") == [
        "go straight take the second right"]
    assert split_instruction("skip the first corridor, then turn right") == [
        "skip the first corridor turn right"]
    # a turn, an end or a stretch of corridor is an instruction of its own
    for sentence, parts in [
            ("turn right, then go past one corner", ["turn right", "go past one corner"]),
            ("go to the end then turn left", ["go to the end", "turn left"]),
            ("walk down this aisle, then turn right", ["walk down this aisle", "turn right"]),
            ("turn around, then go straight", ["turn around", "go straight"])]:
        assert split_instruction(sentence) == parts
    assert split_instruction("go straight, then turn left", "seed") == [
        "go straight", "turn left"]                    # the seed's splitting joins nothing


def test_spoken_splitting_ends_a_turn_around_before_a_direction():
    assert split_instruction("turn around and take the third left") == [
        "turn around", "take the third left"]
    assert split_instruction("make a u-turn and go straight to the end") == [
        "make a u-turn", "go straight to the end"]
    assert split_instruction("turn around and go back") == ["turn around and go back"]
    assert split_instruction("go to the end and turn right") == ["go to the end and turn right"]
    assert split_instruction("turn around and take the third left", "seed") == [
        "turn around and take the third left"]


def test_seed_splitting_is_punctuation_only():
    assert split_instruction("Hey robot, hang a left", "seed") == ["hey robot", "hang a left"]
    assert split_instruction("go to the end then turn left", "seed") == [
        "go to the end then turn left"]
    with pytest.raises(InstructionError, match="unknown splitting 'words'"):
        split_instruction("turn left", "words")


def test_empty_sentence_is_a_clear_error():
    for text in ["", "   ", ", . ! ?", "and then"]:
        with pytest.raises(InstructionError, match="has no words"):
            split_instruction(text)
    with pytest.raises(InstructionError, match="must be text"):
        split_instruction(None)


def test_spoken_splitting_ends_a_going_back_before_a_direction():
    assert split_instruction("go back and take the second right") == [
        "go back", "take the second right"]
    assert split_instruction("do a u turn and go to the end") == ["do a u turn", "go to the end"]
    # the back of a corridor is a place, not a turn
    assert split_instruction("go to the back and turn left") == ["go to the back and turn left"]


def test_and_between_two_turns_ends_the_first():
    assert split_instruction("take the second left and at the end turn right") == [
        "take the second left", "at the end turn right"]
    assert split_instruction("make a right and take the second left and go to the end") == [
        "make a right", "take the second left", "go to the end"]
    assert split_instruction("turn right and go to the end") == ["turn right", "go to the end"]
    assert split_instruction("turn left at the corner and stop") == [
        "turn left at the corner and stop"]
    # a turn passed, counted or refused before "and" belongs to the turn after it
    for sentence in ("skip the first left and turn left at the next one",
                     "let one right go by and take the next right",
                     "count two corners and turn right at the second",
                     "go straight to the end and turn right"):
        assert split_instruction(sentence) == [sentence]


def test_a_refused_turn_joins_the_turn_it_leaves_open():
    assert split_instruction("don't take the first right, take the second") == [
        "don't take the first right take the second"]
    assert split_instruction("don't turn left, turn right") == ["turn right"]
    assert split_instruction("just go forward, don't turn anywhere") == ["just go forward"]
    assert split_instruction("not this right but the next one") == [
        "not this right but the next one"]
    assert split_instruction("don't turn left") == ["don't turn left"]   # nothing else to do


def test_a_piece_that_points_back_joins_the_one_before():
    assert split_instruction("there's a right coming up, take it") == [
        "there's a right coming up take it"]
    assert split_instruction("the first turning on the left, go down there") == [
        "the first turning on the left go down there"]
    assert split_instruction("take it") == ["take it"]


def test_a_reply_word_in_front_is_no_turn():
    assert split_instruction("all right, keep going straight, all the way") == [
        "keep going straight all the way"]
    assert split_instruction("right, go straight to the end") == ["go straight to the end"]
    assert split_instruction("okay, alright go to the end") == ["go to the end"]
    # "right" before anything but a verb is the turn
    assert split_instruction("right, at the first corner") == ["right at the first corner"]
    assert split_instruction("right, then left") == ["right", "left"]


def test_right_before_to_the_end_means_all_the_way():
    assert split_instruction("drive right to the end of the hall") == [
        "drive to the end of the hall"]
    assert split_instruction("go right down to the end of the corridor") == [
        "go down to the end of the corridor"]
    assert split_instruction("follow this hallway right to the end") == [
        "follow this hallway to the end"]
    for turn in ("turn right to the end", "go right at the end", "take a right to the end"):
        assert split_instruction(turn) == [turn]
    assert split_instruction("go right to the end", "seed") == ["go right to the end"]
