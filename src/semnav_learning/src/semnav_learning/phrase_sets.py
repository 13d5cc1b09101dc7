"""Basic instruction sets (thesis 002 §3.2, Fig. 3.2.1): labelled simple instructions of the
classes of Table 3.1-1 (semantic_nav.instruction_classes), generated from the phrase sets in
config/semnav_phrases.yaml."""
import itertools
from dataclasses import dataclass
from pathlib import Path

import yaml

from semantic_nav.instruction_classes import (CLASS_IDS, CLASSES, COUNT_CORNERS, COUNT_SIDE,
                                              NUM_CLASSES, SIDES, TURN, TURN_AT, TURN_CLASSES,
                                              get)

SETS = ("prefix", "suffix", "class1", "class_turn", "prefix_turn", "suffix_turn_keep",
        "suffix_turn_change", "class4", "others")
# Beyond the seed's sets, optional in a phrase file (empty when left out): "the second right"
# (class_turn_counted), counting by passing ("pass one corner and" + a class_turn phrase +
# "at the next one": prefix_turn_change, suffix_turn_next), and "go all the way down and make a
# left" (a class1 phrase + end_join + a class_turn phrase), and counting aloud ("count two
# corners and" + a class_turn phrase + "at the second": prefix_turn_count, suffix_turn_count).
OPTIONAL_SETS = ("class_turn_counted", "prefix_turn_change", "suffix_turn_next", "end_join",
                 "prefix_turn_count", "suffix_turn_count")
# With them (a file of directions as people give them), the place may also be said before the
# turn: recipes(place_first=True). A file without them generates the seed's sentences only.
CHANGE_KINDS = TURN_AT   # kind-B tags: ("second", "third", "end")
COUNTED_KINDS = tuple(kind for kind in TURN_AT if kind != "end")   # ("second", "third")
# core phrase set of a class that is not a turn -> the class: {"class1": 1, "class4": 4}
CORE_SET_CLASS = {c.phrase_set: c.number for c in CLASSES if c.motion != TURN}
# train: the only phrases training sees; validation: phrases that choose between trained
# classifiers (train_semnav --retrain-classifier's monitor); held_out: the final test (§4.2.1).
SPLITS = ("train", "validation", "held_out")


class PhraseSetError(ValueError):
    """A phrase-set file that cannot be used; the message names the set."""


@dataclass(frozen=True)
class Phrase:
    """One phrase chosen from one set; `tag` is the direction, the kind-B kind or the class."""

    set_name: str
    text: str
    split: str              # one of SPLITS
    tag: object = None

    @property
    def held_out(self):
        return self.split == "held_out"


@dataclass(frozen=True)
class Sentence:
    """A generated simple instruction, its class label and the phrases it was built from."""

    text: str
    label: int
    phrases: tuple

    @property
    def counting(self):
        """COUNT_SIDE when a class_turn_counted phrase says it ("take the second right": the
        branches on one side are counted), else COUNT_CORNERS: what the route oracle counts."""
        counted = any(p.set_name == "class_turn_counted" for p in self.phrases)
        return COUNT_SIDE if counted else COUNT_CORNERS


def _phrases(entry, set_name, tag=None):
    if (not isinstance(entry, dict) or not {"train", "held_out"} <= set(entry)
            or not set(entry) <= set(SPLITS)):
        raise PhraseSetError(f"phrase set {set_name!r} needs the keys train and held_out "
                             "(and optionally validation), nothing else")
    return [Phrase(set_name, " ".join(str(text).lower().split()), split, tag)
            for split in SPLITS for text in entry.get(split) or []]


def _by_kind(entry, set_name, kinds):
    """The phrases of a set split by kind ({kind: {train: ..., held_out: ...}}), each tagged
    with its kind; [] for a set left out."""
    return [p for kind in kinds for p in _phrases(entry[kind], set_name, kind)] if entry else []


def load_phrase_sets(path):
    """config/semnav_phrases.yaml -> {set name: [Phrase]} (class_turn expanded to both sides)."""
    config = yaml.safe_load(Path(path).read_text())
    missing = [name for name in SETS if name not in (config or {})]
    if missing:
        raise PhraseSetError(f"{path}: missing phrase set(s) {', '.join(missing)}")
    sets = {name: _phrases(config[name], name)
            for name in ("prefix", "suffix", "class1", "prefix_turn", "suffix_turn_keep",
                         "class4")}
    sets["class_turn"] = [Phrase("class_turn", p.text.format(dir=side), p.split, side)
                          for p in _phrases(config["class_turn"], "class_turn")
                          for side in SIDES]
    sets["suffix_turn_change"] = _by_kind(config["suffix_turn_change"], "suffix_turn_change",
                                          CHANGE_KINDS)
    optional = {name: config.get(name) for name in OPTIONAL_SETS}
    sets["class_turn_counted"] = [
        Phrase("class_turn_counted", p.text.format(dir=side), p.split, (side, p.tag))
        for p in _by_kind(optional["class_turn_counted"], "class_turn_counted", COUNTED_KINDS)
        for side in SIDES]
    for name in ("prefix_turn_change", "prefix_turn_count", "suffix_turn_count"):
        sets[name] = _by_kind(optional[name], name, COUNTED_KINDS)
    for name in ("suffix_turn_next", "end_join"):
        sets[name] = _phrases(optional[name], name) if optional[name] else []
    others = config["others"]
    sets["others"] = [Phrase("others", " ".join(str(t).lower().split()), split, int(label))
                      for split in SPLITS for label, texts in (others.get(split) or {}).items()
                      for t in texts]
    _check_disjoint(sets)
    return sets


def _check_disjoint(sets):
    for name, phrases in sets.items():
        for a, b in itertools.combinations(SPLITS, 2):
            both = {p.text for p in phrases if p.split == a} & {p.text for p in phrases
                                                                if p.split == b}
            if both:
                raise PhraseSetError(f"phrase set {name!r}: {sorted(both)} both {a} and {b}")


def label_of(phrases):
    """Fig. 3.2.1: the class a combination of phrases belongs to, from the sets it chose."""
    by_set = {p.set_name: p for p in phrases}
    if "others" in by_set:
        return by_set["others"].tag
    if "class_turn_counted" in by_set:
        return TURN_CLASSES[by_set["class_turn_counted"].tag]
    if "class_turn" in by_set and "class1" in by_set:        # "go all the way down and ..."
        return TURN_CLASSES[(by_set["class_turn"].tag, "end")]
    for counting in ("prefix_turn_change", "prefix_turn_count"):
        if "class_turn" in by_set and counting in by_set:
            return TURN_CLASSES[(by_set["class_turn"].tag, by_set[counting].tag)]
    for set_name, label in CORE_SET_CLASS.items():
        if set_name in by_set:
            return label
    if "class_turn" in by_set:
        change = by_set.get("suffix_turn_change")
        return TURN_CLASSES[(by_set["class_turn"].tag, change.tag if change else None)]
    raise PhraseSetError(f"no core phrase in {[p.text for p in phrases]}")


def compose(phrases):
    """Join the chosen phrases into one labelled sentence."""
    phrases = tuple(phrases)
    return Sentence(" ".join(p.text for p in phrases), label_of(phrases), phrases)


@dataclass(frozen=True)
class Slot:
    """One box of Fig. 3.2.1 in a recipe: a phrase set, optionally only phrases with `tag`."""

    set_name: str
    tag: object = None
    optional: bool = False


def people_sets(sets):
    """Whether `sets` hold the optional sets of directions as people give them."""
    return bool(sets.get("prefix_turn_change"))


def recipes(label, place_first=False):
    """Fig. 3.2.1 / §3.2 examples: the sequences of sets that generate class `label`;
    `place_first` adds the place said before the turn (beyond the seed)."""
    prefix, suffix = Slot("prefix", optional=True), Slot("suffix", optional=True)
    others = [(prefix, Slot("others", label), suffix)]   # empty unless `others` has the class
    cls = get(label)
    if cls.motion != TURN:
        return [(prefix, Slot(cls.phrase_set), suffix)] + others
    turn = (prefix, Slot("prefix_turn", optional=True), Slot(cls.phrase_set, cls.side))
    # beyond the seed: the place said first ("at the second corner turn right", "two corners
    # down make a left"), the suffix phrase in front of the turn
    place = "suffix_turn_keep" if cls.at is None else "suffix_turn_change"
    extra = [(prefix, Slot(place, cls.at), Slot(cls.phrase_set, cls.side), suffix)
             ] if place_first else []
    if cls.at is None:
        return [turn + (Slot("suffix_turn_keep", optional=True), suffix)] + extra + others
    if cls.at == "end":
        extra.append((prefix, Slot("class1"), Slot("end_join"), Slot(cls.phrase_set, cls.side),
                      suffix))
    else:
        extra.append((prefix, Slot("prefix_turn_change", cls.at), Slot(cls.phrase_set, cls.side),
                      Slot("suffix_turn_next", optional=True), suffix))
        extra.append((prefix, Slot("prefix_turn", optional=True),
                      Slot("class_turn_counted", (cls.side, cls.at)), suffix))
        extra.append((prefix, Slot("prefix_turn_count", cls.at), Slot(cls.phrase_set, cls.side),
                      Slot("suffix_turn_count", cls.at), suffix))
    return [turn + (Slot("suffix_turn_change", cls.at), suffix)] + extra + others


def _choices(sets, slot, split):
    """Phrases a slot may take in a split (training phrases and the split's own); None stands
    for leaving an optional slot out."""
    pool = [p for p in sets[slot.set_name] if p.split in ("train", split)
            and (slot.tag is None or p.tag == slot.tag)]
    return ([None] if slot.optional else []) + pool


def enumerate_sentences(sets, label, split="train"):
    """§3.2: every combination of the sets that generate class `label`, in a fixed order.

    split="train" uses training phrases only; split="held_out" (or "validation") yields only
    sentences with at least one phrase of that split (never seen in training)."""
    if label not in CLASS_IDS or split not in SPLITS:
        raise PhraseSetError(f"unknown class {label!r} or split {split!r}")
    for recipe in recipes(label, people_sets(sets)):
        slots = [_choices(sets, slot, split) for slot in recipe]
        for combination in itertools.product(*slots):
            phrases = [p for p in combination if p is not None]
            if split != "train" and not any(p.split == split for p in phrases):
                continue
            yield compose(phrases)


def enumerate_texts(sets, label, split="train"):
    """The texts of enumerate_sentences(sets, label, split), without building a Sentence each
    (checks over every sentence: millions with the wider sets). A combination of a validation or
    held-out split is enumerated by the first slot that takes a phrase of the split: slots before
    it take training phrases (or nothing), that slot a phrase of the split, later slots any."""
    if label not in CLASS_IDS or split not in SPLITS:
        raise PhraseSetError(f"unknown class {label!r} or split {split!r}")

    def texts(slot, splits):
        pool = [p for p in _choices(sets, slot, split) if p is None or p.split in splits]
        return [p.text if p is not None else None for p in pool]

    for recipe in recipes(label, people_sets(sets)):
        if split == "train":
            layouts = [[texts(slot, ("train",)) for slot in recipe]]
        else:
            layouts = [[texts(slot, ("train",)) for slot in recipe[:k]]
                       + [[t for t in texts(recipe[k], (split,)) if t is not None]]
                       + [texts(slot, ("train", split)) for slot in recipe[k + 1:]]
                       for k in range(len(recipe))]
        for pools in layouts:
            yield from _joined(pools)


def _joined(pools):
    """Every combination of one text from each pool (None: the slot left out), its texts joined
    by spaces, in itertools.product's order. Built slot by slot, one concatenation per text
    rather than a join over a generator: the checks over every sentence (millions) run about
    three times faster."""
    texts = [None]                  # None: no phrase yet
    for pool in pools:
        texts = [left if text is None else text if left is None else f"{left} {text}"
                 for left in texts for text in pool]
    return ["" if text is None else text for text in texts]


def sample_sentence(sets, label, rng, split="train"):
    """§3.4: one random sentence of class `label` (uniform over recipes, then over slots)."""
    if label not in CLASS_IDS or split not in SPLITS:
        raise PhraseSetError(f"unknown class {label!r} or split {split!r}")
    options = [[_choices(sets, slot, split) for slot in recipe]
               for recipe in recipes(label, people_sets(sets))]
    options = [pools for pools in options if all(pools)]
    if not options:
        raise PhraseSetError(f"no phrases for class {label} in split {split!r}")
    pools = options[rng.integers(len(options))]
    for _ in range(1000):   # held-out / validation: redraw until a phrase of the split is used
        phrases = [c for c in (pool[rng.integers(len(pool))] for pool in pools) if c]
        if split == "train" or any(p.split == split for p in phrases):
            return compose(phrases)
    raise PhraseSetError(f"class {label}: no {split} phrase drawn in 1000 tries")


@dataclass
class PhrasingScore:
    """Z_w on one split's phrasings: hits and sentences per class, misses and uses per phrase
    of the split (each phrase of a missed sentence is counted)."""

    per_class: dict
    per_phrase: dict

    @property
    def hits(self):
        return sum(hits for hits, _ in self.per_class.values())

    @property
    def accuracy(self):
        return self.hits / sum(total for _, total in self.per_class.values())

    def missed_phrases(self):
        """[(phrase, misses, uses)] of the split's phrases with misses, most missed first."""
        rows = [(text, missed, used) for text, (missed, used) in self.per_phrase.items() if missed]
        return sorted(rows, key=lambda row: (-row[1] / row[2], -row[1], row[0]))


def score_phrasings(sets, classify, count, rng, split="held_out"):
    """§4.2.1's "new instructions with similar meanings": `count` sentences of `split`, classes in
    turn, each classified by `classify(text) -> [class, ...]` (right if it is [label])."""
    per_class = {label: [0, 0] for label in CLASS_IDS}
    per_phrase = {}
    for i in range(count):
        label = CLASS_IDS[i % NUM_CLASSES]
        sentence = sample_sentence(sets, label, rng, split)
        right = classify(sentence.text) == [label]
        per_class[label][0] += right
        per_class[label][1] += 1
        for phrase in (p for p in sentence.phrases if p.split == split):
            tally = per_phrase.setdefault(phrase.text, [0, 0])
            tally[0] += not right
            tally[1] += 1
    return PhrasingScore(per_class, per_phrase)
