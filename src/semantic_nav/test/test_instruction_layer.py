"""Instruction layer (thesis 002 §2.2.3, §3.1) on the seed's example sentences."""
import numpy as np
import pytest

from semantic_nav.instruction_layer import (FollowableConfig, UnfollowableInstruction,
                                            check_followable, convert_instruction, corners_asked,
                                            english_fraction, number_value, ordinal_text,
                                            read_counts, read_transcript, sentence_vector,
                                            tokenise)
from semantic_nav.splitting import InstructionError, split_instruction
from semantic_nav.word_vectors import WordVectors, default_cache_dir, load_compact_cache


def test_tokenise_lower_case_and_clitics():
    assert tokenise("I'd like you to Turn RIGHT at the 2nd corner") == [
        "i", "'d", "like", "you", "to", "turn", "right", "at", "the", "second", "corner"]
    assert tokenise("don't make a u-turn") == ["do", "n't", "make", "a", "u-turn"]
    # the verb of "can't" / "won't" in full, as the phrase sets write it
    assert tokenise("until you can't, won't") == ["until", "you", "can", "n't", "will", "n't"]
    assert tokenise("ca wo") == ["ca", "wo"]


def test_numerals_become_the_words_of_the_phrase_sets():
    assert tokenise("turn left 2 corners down") == ["turn", "left", "two", "corners", "down"]
    assert tokenise("at the 1st, 3rd or 10th corner, 0 or 10") == [
        "at", "the", "first", "third", "or", "tenth", "corner", "zero", "or", "ten"]
    # beyond ten, and digits inside other words, stay as they are (GloVe has them)
    assert tokenise("room 101 on the 11th floor, b2 wing") == [
        "room", "101", "on", "the", "11th", "floor", "b2", "wing"]


def test_number_homophones_before_counted_plurals_are_read_as_numbers():
    """Speech recognition's "to corners" for "two corners", "free" for "three"."""
    assert read_counts("turn left to corners down") == "turn left two corners down"
    assert tokenise("pass too rights and go to the end") == [
        "pass", "two", "rights", "and", "go", "to", "the", "end"]
    assert read_counts("I need you to do corners down") == "I need you to two corners down"
    assert read_counts("Free Intersections along") == "three intersections along"
    for kept in ["go to the corner to", "I need you to turn left", "go to corner and turn left",
                 "walk to intersection and turn right", "do turn left", "to corners-store"]:
        assert read_counts(kept) == kept


def test_a_transcript_reads_a_homophone_before_a_bare_singular_as_a_number():
    """Heard, "to intersection down" is "two intersections down"; not when a number or a name
    follows, nor with an article."""
    assert read_transcript("make a right To intersection now") == (
        "make a right two intersections now")
    assert read_transcript("hang a right free corner from here") == (
        "hang a right three corners from here")
    for kept in ["go to the corner", "go to corner three", "go to intersection 2",
                 "go to intersection number two", "go to junction #2", "go to corner 2nd",
                 "head to cornerstone hall", "go to corner-store",
                 "go to intersection second"]:
        assert read_transcript(kept) == kept
    assert read_counts("go to corner and turn left") == "go to corner and turn left"


def test_a_transcript_drops_its_commas_but_not_its_sentence_ends():
    """Whisper's commas mark pauses, not instruction ends; "." still splits."""
    heard = "Now, proceed down this hallway to the end, and when you get there, go right, please."
    assert read_transcript(heard) == (
        "Now proceed down this hallway to the end and when you get there go right please.")
    assert split_instruction(read_transcript(heard)) == [
        "now proceed down this hallway to the end and when you get there go right please"]
    assert split_instruction(heard) == [      # typed, its commas split as the seed's do
        "now proceed down this hallway to the end", "when you get there go right please"]
    assert split_instruction(read_transcript("Go to the end. Turn left; thanks")) == [
        "go to the end", "turn left thanks"]


def test_will_is_read_in_full():
    assert tokenise("you'll make a left") == ["you", "will", "make", "a", "left"]


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


@pytest.mark.parametrize("token, value", [
    ("99th", (99, True)), ("4", (4, False)), ("fourth", (4, True)), ("twenty-first", (21, True)),
    ("ninety-nine", (99, False)), ("hundredth", (100, True)), ("third", (3, True)),
    ("corner", None), ("second-hand", None)])
def test_number_value(token, value):
    assert number_value(token) == value


def test_ordinal_text():
    assert [ordinal_text(n) for n in (1, 2, 3, 4, 11, 12, 13, 21, 22, 99, 111)] == [
        "1st", "2nd", "3rd", "4th", "11th", "12th", "13th", "21st", "22nd", "99th", "111th"]


@pytest.mark.parametrize("text, asked", [
    ("turn left at the 99th corner", [99]), ("turn left at the second corner", [2]),
    ("turn right after the third corner", [4]), ("after one corner turn left", [2]),
    ("go two corners down", [2]), ("five corners down", [5]), ("take the fifth left", [5]),
    ("turn left at corner number four", [4]), ("at corner three turn right", [3]),
    ("turn left at the twenty-first intersection", [21]),
    ("turn left at the corner 5 metres ahead", []), ("go straight 20 meters", []),
    ("first go straight to the end", []), ("turn left at the corner", [])])
def test_corners_asked(text, asked):
    assert corners_asked(text) == asked


@pytest.mark.parametrize("sentence, shown", [
    ("turn left at the 99th corner", "99th"), ("go to the end, then take the fourth right", "4th"),
    ("Turn right after the third corner.", "4th"), ("turn left at the zeroth corner", "0th")])
def test_corners_beyond_the_third_are_refused_with_a_spoken_reason(sentence, shown):
    with pytest.raises(UnfollowableInstruction) as caught:
        check_followable(sentence)
    assert f"asks for the {shown} corner; the instruction classes count corners from the 1st " \
           f"to the 3rd" in str(caught.value)
    assert caught.value.spoken == (f"Sorry, I can only count corners up to the third one, and "
                                   f"you asked for the {shown}. I am staying here.")


@pytest.mark.parametrize("sentence", [
    "turn left at the third corner", "go straight to the end, then turn left at the 2nd corner",
    "after the second corner turn right", "go three corners down then turn left",
    "turn left at the corner 5 metres ahead"])
def test_counts_the_classes_know_pass(sentence):
    check_followable(sentence)


def frequency_ordered(words):
    """WordVectors whose row order is the given frequency order (as GloVe's)."""
    return WordVectors(words, np.zeros((len(words), 2), dtype=np.float32), "ranked")


def test_english_fraction_counts_common_words_only():
    vectors = frequency_ordered(["the", "to", "go", "end", "la", "turn", "left", "gehe"])
    config = FollowableConfig(common_words=7)            # "gehe" is the 8th: not common
    assert english_fraction("go to the end", vectors, config) == (4, 4)
    assert english_fraction("gehe zum ende", vectors, config) == (0, 3)
    # "la" is common in the vocabulary but one of FOREIGN_WORDS; numbers are not words
    assert english_fraction("turn left at la 2nd", vectors, config) == (2, 4)
    assert english_fraction("直走到尽头然后左转", vectors, config) == (0, 1)


def test_a_sentence_of_uncommon_words_is_refused_as_not_english():
    vectors = frequency_ordered(["the", "to", "go", "end", "turn", "right", "veer"])
    config = FollowableConfig(common_words=6)
    with pytest.raises(UnfollowableInstruction) as caught:
        check_followable("gehe geradeaus bis zum ende", vectors, config)
    assert str(caught.value) == ("only 0 of its 5 words are common English words (among the 6 "
                                 "most frequent of ranked), fewer than 60%: not English, or not "
                                 "directions")
    assert caught.value.spoken == ("Sorry, I can only follow directions in English. I am "
                                   "staying here.")
    with pytest.raises(UnfollowableInstruction):
        check_followable("直走到尽头然后左转", vectors, config)
    check_followable("go to the end", vectors, config)
    check_followable("veer right", vectors, config)      # one uncommon word beside a common one
    with pytest.raises(UnfollowableInstruction):
        check_followable("veer zum", vectors, config)


GLOVE = default_cache_dir()
FOREIGN = ["gehe geradeaus bis zum ende und dann links", "biege an der zweiten ecke rechts ab",
           "va tout droit jusqu'au bout puis tourne à gauche", "tourne à droite au deuxième coin",
           "sigue recto hasta el final y gira a la izquierda",
           "toma la tercera a la izquierda por favor",
           "vai dritto fino alla fine e poi gira a sinistra", "gira a destra al secondo angolo",
           "ga rechtdoor tot het einde en dan links", "neem de derde links alsjeblieft",
           "siga em frente até o fim e depois vire à esquerda", "直走到尽头然后左转",
           # written after FOREIGN_WORDS was, as a check
           "lauf bis zum ende des ganges und bieg dann rechts ab",
           "au bout du couloir tournez à droite", "marche jusqu'au fond et attends moi",
           "al final del pasillo gira a la derecha",
           "ve todo recto y en el segundo cruce a la izquierda",
           "in fondo al corridoio gira a destra", "aan het einde van de gang rechtsaf",
           "ga rechtdoor en neem dan de eerste links", "no fim do corredor vire à direita"]
ENGLISH = ["go down the hall and make a left at the second door",
           "head towards the elevators then hang a right", "veer right",
           "keep going past the vending machine until the corridor ends",
           "okay robot, straight ahead, then left at the crossroads",
           "proceed to the end of the corridor then bear left", "go to the den and wait",
           "kindly veer right at the third junction", "drive on and swing left"]


@pytest.mark.skipif(not (GLOVE / "vocab.txt").is_file(), reason="no GloVe cache (scripts/setup)")
def test_on_glove_6b_foreign_directions_are_refused_and_english_ones_pass():
    vectors = load_compact_cache(GLOVE)
    for sentence in FOREIGN:
        with pytest.raises(UnfollowableInstruction, match="common English words"):
            check_followable(sentence, vectors)
    for sentence in ENGLISH:
        check_followable(sentence, vectors)


def test_words_outside_the_phrase_vocabulary_are_skipped(tmp_path):
    from semantic_nav.instruction_layer import phrase_vocabulary
    phrases = tmp_path / "phrases.yaml"
    phrases.write_text("class_turn:\n  train: [\"take a {dir}\", \"turn {dir}\"]\n"
                       "class_turn_counted:\n  second:\n    train: [\"skip two {dir}s\"]\n")
    vocabulary = phrase_vocabulary(phrases)
    assert vocabulary == {"take", "a", "right", "left", "turn", "skip", "two", "rights", "lefts"}
    words = WordVectors(["take", "a", "lift", "left", "turn"], np.eye(5, dtype=np.float32), "t")
    vector = sentence_vector("take a lift turn", words, vocabulary)
    assert vector.oov == ["lift"] and vector.vectors.shape == (3, 5)
    assert sentence_vector("take a lift turn", words).oov == []          # every GloVe word
    with pytest.raises(InstructionError, match="vocabulary of t and the phrase sets"):
        sentence_vector("lift", words, vocabulary)
    (tmp_path / "empty.yaml").write_text("{}\n")
    with pytest.raises(InstructionError, match="empty.yaml: no phrases in it"):
        phrase_vocabulary(tmp_path / "empty.yaml")
    with pytest.raises(InstructionError, match="phrase vocabulary .*none.yaml"):
        phrase_vocabulary(tmp_path / "none.yaml")


def test_the_default_follower_reads_a_misheard_side_as_the_side():
    """Speech recognition hears "lift" for "left": a GloVe word outside the phrase sets, one
    letter from "left"; the follower reads it as "left" and says so (without misheard_edits it
    skips it and names it, as it does a word GloVe does not know)."""
    from semantic_nav.follower import DirectionFollower, ModelMissingError
    from semantic_nav.word_vectors import WordVectorsError
    try:
        follower = DirectionFollower.from_files()
    except (ModelMissingError, WordVectorsError) as error:
        pytest.skip(str(error))
    assert follower.start("robot move forward and take a lift turn for me") == [3]
    assert follower.corrections == [("lift", "left")] and follower.unknown_words == []
    assert follower.start("robot please take the second right for me") == [5]
    assert follower.unknown_words == [] and follower.corrections == []
    # what it follows is what it read: "the second left" counts left-hand branches
    assert follower.start("take the second lift") == follower.start("take the second left")
    follower.start("take the second lift")
    assert follower.instructions == ["take the second left"] and follower.countings == ["side"]
    with pytest.raises(UnfollowableInstruction, match="4th corner"):
        follower.start("take the fourth lift")
    follower.config.misheard_edits = 0
    follower.start("robot move forward and take a lift turn for me")
    assert follower.unknown_words == ["lift"] and follower.corrections == []


@pytest.mark.parametrize("text, counting", [
    ("take the second right", "side"),
    ("take the 2nd left", "side"),
    ("go down and take the third left-hand turning", "side"),
    ("take the second right hand turn", "side"),
    ("turn at the second opening on your right", "side"),
    ("take the second on the right", "side"),
    ("skip the first right and take the next one", "side"),
    ("pass two lefts and turn left", "side"),
    ("let one left go by and take the next", "side"),
    ("not this right but the next one", "side"),
    ("not the next two lefts but the one after", "side"),
    ("turn right at the second corner", "corners"),
    ("turn right at the second right-hand corner", "corners"),
    ("turn right at the second right hand corner", "corners"),
    ("turn right at the second corner on the right", "corners"),
    ("skip the first right corner and turn right at the next", "corners"),
    ("at the second junction turn left", "corners"),
    ("turn left after the second corner", "corners"),
])
def test_counting_mode(text, counting):
    from semantic_nav.instruction_layer import counting_mode
    assert counting_mode(text) == counting
    assert counting_mode(text, label=2) == "corners"       # class 2 counts nothing
