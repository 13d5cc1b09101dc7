"""Phrase-set generator (thesis 002 §3.2) on the seed's three worked examples and its splits."""
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
import pytest
import yaml

from semantic_nav.instruction_layer import tokenise
from semantic_nav.splitting import split_instruction
from semantic_nav.instruction_classes import CLASS_IDS
from semnav_learning.phrase_sets import (OPTIONAL_SETS, SETS, Phrase, PhraseSetError, _choices,
                                         compose, enumerate_sentences, enumerate_texts,
                                         load_phrase_sets, recipes, sample_sentence,
                                         score_phrasings)
from semantic_nav.word_vectors import WordVectorsError, load_compact_cache
from tamp_resources import resource

CONFIG = resource("config") / "semnav_phrases.yaml"


@pytest.fixture(scope="module")
def sets():
    return load_phrase_sets(CONFIG)


@dataclass
class Generated:
    """One pass over the texts of every training sentence of a class (millions in all)."""

    texts: set = field(default_factory=set)
    count: int = 0
    every_97th: list = field(default_factory=list)


@pytest.fixture(scope="module")
def train_sentences(sets):
    """enumerate_texts: the texts of enumerate_sentences without a Sentence each (the same
    texts in the same order: test_texts_are_the_texts_of_the_sentences)."""
    out = {}
    for label in CLASS_IDS:
        texts = list(enumerate_texts(sets, label, "train"))
        out[label] = Generated(set(texts), len(texts), texts[::97])
    return out


def first_phrases(node):
    """A phrase file's content cut to the first phrase of every list: every set, kind, split
    and class is kept, so every recipe generates every combination of sets it has."""
    if isinstance(node, list):
        return node[:1]
    if isinstance(node, dict):
        return {key: first_phrases(value) for key, value in node.items()}
    return node


@pytest.fixture(scope="module")
def few_sets(tmp_path_factory):
    """The phrase sets with one phrase per list: whole Sentences for every combination of sets
    of every class and split in a second. A sentence's label and split follow from the sets
    and kinds its phrases were taken from (label_of, _choices), never from their words."""
    path = tmp_path_factory.mktemp("phrases") / "first_phrases.yaml"
    path.write_text(yaml.safe_dump(first_phrases(yaml.safe_load(CONFIG.read_text()))))
    return load_phrase_sets(path)


def _find(sets, name, text):
    return next(p for p in sets[name] if p.text == text)


def test_worked_example_class_1(sets, train_sentences):
    # 'Could you' + 'go straight till the end' + 'please' -> Class 1
    sentence = compose([_find(sets, "prefix", "could you"),
                        _find(sets, "class1", "go straight till the end"),
                        _find(sets, "suffix", "please")])
    assert sentence.label == 1
    assert sentence.text == "could you go straight till the end please"
    assert sentence.text in train_sentences[1].texts


def test_worked_example_class_2(sets, train_sentences):
    # 'Go straight and' + 'make a right turn' + 'please' -> Class 2
    sentence = compose([_find(sets, "prefix_turn", "go straight and"),
                        _find(sets, "class_turn", "make a right turn"),
                        _find(sets, "suffix", "please")])
    assert sentence.label == 2
    assert sentence.text in train_sentences[2].texts


def test_worked_example_class_5(sets, train_sentences):
    # 'Please' + 'make a right turn' + 'at the second intersection' -> Class 5
    sentence = compose([_find(sets, "prefix", "please"),
                        _find(sets, "class_turn", "make a right turn"),
                        _find(sets, "suffix_turn_change", "at the second intersection")])
    assert sentence.label == 5
    assert sentence.text in train_sentences[5].texts
    left = compose([sentence.phrases[0], _find(sets, "class_turn", "make a left turn"),
                    sentence.phrases[2]])
    assert left.label == 6


def test_directions_as_people_give_them(sets):
    """Beyond the seed's sets: counting by passing, "the N-th right", "all the way down and"."""
    left, right = (_find(sets, "class_turn", t) for t in ("turn left", "make a right"))
    passing = _find(sets, "prefix_turn_change", "pass one corner and")
    assert compose([passing, left, _find(sets, "suffix_turn_next", "at the next one")]).label == 6
    assert compose([_find(sets, "prefix_turn_change", "pass two corners and"), right]).label == 7
    second_right = compose([_find(sets, "class_turn_counted", "take the second right")])
    assert (second_right.label, second_right.counting) == (5, "side")
    assert compose([_find(sets, "class_turn_counted", "skip two lefts and take the one after")]
                   ).label == 8
    counted = compose([_find(sets, "prefix_turn_count", "count three corners and"), right,
                       next(p for p in sets["suffix_turn_count"] if p.text == "at the third")])
    assert (counted.text, counted.label, counted.counting) == (
        "count three corners and make a right at the third", 7, "corners")
    down = compose([_find(sets, "class1", "go all the way down"), _find(sets, "end_join", "and"),
                    _find(sets, "class_turn", "make a left")])
    assert (down.text, down.label) == ("go all the way down and make a left", 10)
    assert compose([passing, left]).counting == "corners"      # corners over both sides


def test_no_words_are_generated_for_two_classes(sets):
    """A Class 1 phrase and end_join (Class 9 / 10 with a turn after them) must not spell a
    prefix_turn phrase (Class 2 / 3 with the same turn): "go straight" + "and" + "turn left"."""
    joined = {f"{c.text} {j.text}" for c in sets["class1"] for j in sets["end_join"]}
    assert not joined & {p.text for p in sets["prefix_turn"]}


def test_phrase_files_without_the_optional_sets_still_load(tmp_path):
    config = yaml.safe_load(CONFIG.read_text())
    for name in OPTIONAL_SETS:
        del config[name]
    plain = tmp_path / "seed_sets.yaml"
    plain.write_text(yaml.safe_dump(config))
    sets = load_phrase_sets(plain)
    assert all(sets[name] == [] for name in OPTIONAL_SETS)
    rng = np.random.default_rng(1)
    assert all(sample_sentence(sets, label, rng).label == label for label in CLASS_IDS)
    # the seed's sentences only: the place is said after the turn
    texts = set(enumerate_texts(sets, 5))
    assert "turn right at the second corner" in texts
    assert "at the second corner turn right" not in texts


def test_suffix_turn_kinds(sets):
    turn = _find(sets, "class_turn", "turn left")
    assert compose([turn, _find(sets, "suffix_turn_keep", "at the corner")]).label == 3
    assert compose([turn, _find(sets, "suffix_turn_change", "at the third corner")]).label == 8
    assert compose([turn, _find(sets, "suffix_turn_change", "at the end of this aisle")]
                   ).label == 10


def test_every_class_is_generated_with_its_own_label(train_sentences, few_sets):
    for label, generated in train_sentences.items():
        assert generated.count > 100, label
    for label in CLASS_IDS:
        for split in ("train", "validation", "held_out"):
            sentences = list(enumerate_sentences(few_sets, label, split))
            assert sentences and {s.label for s in sentences} == {label}, (label, split)


def test_texts_are_the_texts_of_the_sentences(few_sets):
    """enumerate_texts yields enumerate_sentences' texts: in the same order for training (every
    97th training sentence above), in another order for the other splits."""
    for label in CLASS_IDS:
        assert list(enumerate_texts(few_sets, label)) == [
            s.text for s in enumerate_sentences(few_sets, label)], label
        for split in ("validation", "held_out"):
            assert Counter(enumerate_texts(few_sets, label, split)) == Counter(
                s.text for s in enumerate_sentences(few_sets, label, split)), (label, split)


def test_enumeration_counts_follow_the_set_sizes(sets, train_sentences):
    # Class 4 = (prefix + none) x class4 x (suffix + none), training phrases only
    n = Counter(p.set_name for p in (p for v in sets.values() for p in v) if p.split == "train")
    assert train_sentences[4].count == (n["prefix"] + 1) * n["class4"] * (n["suffix"] + 1)
    turns_right = sum(1 for p in sets["class_turn"] if p.split == "train" and p.tag == "right")
    others_2 = sum(1 for p in sets["others"] if p.split == "train" and p.tag == 2)
    # the seed's recipe, the place said first ("at the next corner turn right"), others
    assert train_sentences[2].count == (n["prefix"] + 1) * (n["suffix"] + 1) * (
        (n["prefix_turn"] + 1) * turns_right * (n["suffix_turn_keep"] + 1)
        + n["suffix_turn_keep"] * turns_right + others_2)


def test_the_place_can_be_said_before_the_turn(train_sentences):
    assert "at the second corner turn right" in train_sentences[5].texts
    assert "two corners down make a left" in train_sentences[6].texts
    assert "at the end of the corridor turn left" in train_sentences[10].texts
    assert "at the next corner turn right" in train_sentences[2].texts


def test_held_out_sentences_never_occur_in_training(sets, train_sentences, few_sets):
    for label in CLASS_IDS:
        held = list(enumerate_texts(sets, label, "held_out"))
        assert held and train_sentences[label].texts.isdisjoint(held)
        # training sentences take training phrases only (every combination of sets)
        assert not any(p.split != "train" for s in enumerate_sentences(few_sets, label)
                       for p in s.phrases)
    # enumerate_texts yields exactly enumerate_sentences' texts (here on the smallest class)
    assert Counter(enumerate_texts(sets, 4, "held_out")) == Counter(
        s.text for s in enumerate_sentences(sets, 4, "held_out"))
    assert all(any(p.held_out for p in s.phrases)
               for s in enumerate_sentences(sets, 1, "held_out"))


def test_validation_phrasings_are_neither_trained_on_nor_tested(sets, train_sentences):
    rng = np.random.default_rng(2)
    for label in CLASS_IDS:
        sentences = [sample_sentence(sets, label, rng, "validation") for _ in range(30)]
        assert all(s.label == label for s in sentences)
        assert all(any(p.split == "validation" for p in s.phrases) for s in sentences)
        assert not any(p.held_out for s in sentences for p in s.phrases)
        assert not {s.text for s in sentences} & train_sentences[label].texts
    # held-out sentences draw only on training and held-out phrases
    for label in CLASS_IDS:
        for recipe in recipes(label, place_first=True):
            for slot in recipe:
                assert not any(p is not None and p.split == "validation"
                               for p in _choices(sets, slot, "held_out"))


def test_held_out_sampling_ignores_validation_phrases(tmp_path):
    # the held-out test draws the same sentences with or without validation phrases in the file
    config = yaml.safe_load(CONFIG.read_text())
    entries = [config[name] for name in SETS if name not in ("suffix_turn_change", "others")]
    for entry in entries + list(config["suffix_turn_change"].values()):
        entry.pop("validation", None)
    plain = tmp_path / "phrases.yaml"
    plain.write_text(yaml.safe_dump(config))
    loaded = [load_phrase_sets(path) for path in (CONFIG, plain)]
    draws = [[sample_sentence(sets, label, np.random.default_rng(9), "held_out").text
              for label in CLASS_IDS] for sets in loaded]
    assert draws[0] == draws[1]
    with pytest.raises(PhraseSetError, match="no validation phrase"):
        sample_sentence(load_phrase_sets(plain), 4, np.random.default_rng(0), "validation")


def test_generated_sentences_are_single_simple_instructions(train_sentences):
    for generated in train_sentences.values():
        for text in generated.every_97th:
            assert split_instruction(text) == [text]


def test_sampling_is_reproducible_and_labelled(sets):
    a = [sample_sentence(sets, 7, np.random.default_rng(3)).text for _ in range(1)]
    b = [sample_sentence(sets, 7, np.random.default_rng(3)).text for _ in range(1)]
    assert a == b
    rng = np.random.default_rng(0)
    held = [sample_sentence(sets, 9, rng, "held_out") for _ in range(20)]
    assert all(s.label == 9 and any(p.held_out for p in s.phrases) for s in held)


def test_phrasing_score_counts_misses_per_phrase(sets):
    # a classifier right on every sentence but those with "veer": it misses exactly them
    rng = np.random.default_rng(5)
    sentences = [sample_sentence(sets, i % 10 + 1, rng, "held_out") for i in range(400)]
    by_text = {s.text: s.label for s in sentences}
    score = score_phrasings(sets, lambda text: [0 if "veer" in text else by_text[text]], 400,
                           np.random.default_rng(5))
    veered = [s for s in sentences if "veer" in s.text]
    assert veered
    assert score.hits == 400 - len(veered)
    assert score.accuracy == pytest.approx(1 - len(veered) / 400)
    assert score.per_class[4] == [40, 40]          # class 4 has no turn phrase
    missed = {text: (m, n) for text, m, n in score.missed_phrases()}
    assert missed["veer right"][0] == missed["veer right"][1] > 0
    assert missed["veer left"][0] == missed["veer left"][1] > 0
    assert score.missed_phrases()[0][1] == score.missed_phrases()[0][2]   # 100 % missed first
    uses = sum(n for m, n in score.per_phrase.values())
    assert uses == sum(sum(p.held_out for p in s.phrases) for s in sentences)


def test_bad_requests_are_clear_errors(sets, tmp_path):
    with pytest.raises(PhraseSetError, match="unknown class 11"):
        list(enumerate_sentences(sets, 11))
    broken = tmp_path / "p.yaml"
    broken.write_text("prefix: {train: [please]}\n")
    with pytest.raises(PhraseSetError, match="missing phrase set"):
        load_phrase_sets(broken)
    config = yaml.safe_load(CONFIG.read_text())
    config["suffix"]["tested"] = ["and halt"]
    broken.write_text(yaml.safe_dump(config))
    with pytest.raises(PhraseSetError, match="'suffix' needs the keys train and held_out"):
        load_phrase_sets(broken)
    config["suffix"].pop("tested")
    config["suffix"]["validation"] = ["and halt"]
    broken.write_text(yaml.safe_dump(config))
    with pytest.raises(PhraseSetError, match=r"\['and halt'\] both validation and held_out"):
        load_phrase_sets(broken)
    with pytest.raises(PhraseSetError, match="no core phrase"):
        compose([Phrase("prefix", "please", "train")])


def test_every_phrase_word_has_a_glove_vector(sets):
    try:
        vectors = load_compact_cache()
    except WordVectorsError as error:
        pytest.skip(str(error))
    words = {w for phrases in sets.values() for p in phrases for w in tokenise(p.text)}
    assert sorted(w for w in words if w not in vectors) == []


def test_the_follower_counts_as_the_phrase_sets_say(sets):
    """The counting the evaluation judges a sentence by (the phrase set it was built with) is
    the counting the follower reads from its words, for sentences of classes 5-8 of every
    split."""
    from semantic_nav.instruction_layer import counting_mode
    rng = np.random.default_rng(0)
    for split in ("train", "validation", "held_out"):
        for label in (5, 6, 7, 8):
            for _ in range(300):
                sentence = sample_sentence(sets, label, rng, split)
                assert counting_mode(sentence.text, label) == sentence.counting, sentence.text
