"""Instruction layer, conversion stage (thesis 002 §2.2.3.2 and §3.1): sentence -> simple
instructions -> tokens -> sentence vectors (one GloVe vector per word)."""
import os
import re
from collections.abc import Collection
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from semantic_nav.instruction_classes import (COUNT_CORNERS, COUNT_SIDE, COUNTING_IDS,
                                              MAX_CORNER)
from semantic_nav.splitting import TOKEN, InstructionError, split_instruction

if TYPE_CHECKING:
    from semantic_nav.word_vectors import WordVectors

# Numerals as words: typed and transcribed instructions write "2nd corner" or "2 corners", the
# phrase sets (and so LSTM_w) know "second" and "two"; GloVe puts "2nd" about as near "third"
# (cosine 0.58) as "second" (0.60).
ORDINAL = re.compile(r"^(\d+)(?:st|nd|rd|th)$")
ORDINAL_WORDS = ("zeroth", "first", "second", "third", "fourth", "fifth", "sixth", "seventh",
                 "eighth", "ninth", "tenth")
CARDINAL_WORDS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight",
                  "nine", "ten")
# A speech recogniser writes a counted number as its homophone: "two" as "to", "too" or "do",
# "three" as "free" or "tree" ("turn left to corners down", "free intersections along"). Before
# a plural of the things directions count only the number makes sense (read_counts, typed or
# heard). In a transcript a bare singular after one is the number too ("make a right to
# intersection down": the recogniser loses a plural's "s" more often than a speaker drops "the");
# typed, "go to corner and turn left" names a place (read_transcript).
NUMBER_HOMOPHONES = {"to": "two", "too": "two", "do": "two", "free": "three", "tree": "three"}
COUNTED_PLURALS = frozenset((
    "corners", "intersections", "junctions", "crossings", "crossroads", "turnings", "turns",
    "lefts", "rights", "openings", "branches", "hallways", "corridors", "exits"))
COUNTED_SINGULARS = {"corner": "corners", "intersection": "intersections",
                     "junction": "junctions", "crossing": "crossings", "opening": "openings"}
HOMOPHONE_PLURAL = re.compile(
    rf"\b({'|'.join(NUMBER_HOMOPHONES)})\s+({'|'.join(sorted(COUNTED_PLURALS))})\b(?!-)",
    re.IGNORECASE)
# ... not one that a number or a name follows ("to intersection three", "to corner-store")
HOMOPHONE_SINGULAR = re.compile(
    rf"\b({'|'.join(NUMBER_HOMOPHONES)})\s+({'|'.join(COUNTED_SINGULARS)})\b(?![-'])"
    rf"(?!\s+(?:number|no|{'|'.join(CARDINAL_WORDS + ORDINAL_WORDS)})\b)(?!\s+[#\d])",
    re.IGNORECASE)
# Its commas guess at pauses, not at where the speaker's instructions end: "proceed down this
# hallway to the end, and when you get there, go right" is one instruction (class 9).
TRANSCRIPT_PAUSES = re.compile(r"\s*[,;]+\s*")
# The verb of a negative contraction as split off its "n't" ("can't" -> "ca" "n't"): GloVe 6B
# knows "ca", the phrase sets only "can" ("until you cannot continue").
CONTRACTED_VERBS = {"ca": "can", "wo": "will", "sha": "shall"}
# A side said with "-hand" is the side: "take the right-hand turn" is "take the right turn"
# (GloVe 6B has no "right-hand"; "the second right-hand corner" still counts corners).
SIDE_HAND = {"right-hand": "right", "left-hand": "left"}
# A clitic the phrase sets write in full: "you'll make a left" reads as "you will make a left"
# (speech recognition hears a lead-in "uh, walk" as "I'll walk").
CLITICS = {"'ll": "will"}


@dataclass
class SentenceVector:
    """The word vectors of one simple instruction (§2.2.3.2) and what was left out."""

    text: str                       # the simple instruction
    tokens: list[str]               # its lower-case tokens
    vectors: np.ndarray             # float32 (n_known_tokens, dim), in token order
    oov: list[str] = field(default_factory=list)  # tokens without a word vector (skipped)


def read_transcript(text: str) -> str:
    """A speech recogniser's transcript as the follower reads it (beyond the seed, whose phone
    recogniser wrote no punctuation): its commas and semicolons dropped (TRANSCRIPT_PAUSES) and a
    number's homophone before a bare counted singular read as the number ("to intersection" ->
    "two intersections", HOMOPHONE_SINGULAR). Sentence ends (. ? !) still split."""
    return HOMOPHONE_SINGULAR.sub(_as_number, TRANSCRIPT_PAUSES.sub(" ", text).strip())


def read_counts(text: str) -> str:
    """`text` with a number's homophone before a counted plural written as the number ("to
    corners" -> "two corners", "free intersections" -> "three intersections"; HOMOPHONE_PLURAL)."""
    return HOMOPHONE_PLURAL.sub(_as_number, text)


def _as_number(match: re.Match[str]) -> str:
    """The number a homophone stands for, and the plural of what it counts."""
    homophone, counted = match.group(1).lower(), match.group(2).lower()
    return f"{NUMBER_HOMOPHONES[homophone]} {COUNTED_SINGULARS.get(counted, counted)}"


def tokenise(text: str) -> list[str]:
    """Lower-case word tokens of one simple instruction, numbers' homophones before counted
    things as the numbers (read_counts), numerals up to ten as words, "right-hand" as "right"
    (SIDE_HAND), a verb before "n't" in full ("can't" -> "can" "n't") and "'ll" as "will"
    (CLITICS)."""
    tokens = [SIDE_HAND.get(token) or numeral_as_word(token)
              for token in TOKEN.findall(read_counts(text.lower()))]
    return [CONTRACTED_VERBS.get(token, token) if following == "n't" else
            CLITICS.get(token, token) for token, following in zip(tokens, tokens[1:] + [""])]


def numeral_as_word(token: str) -> str:
    """"2nd" -> "second", "3" -> "three" (0 to 10); any other token unchanged."""
    ordinal = ORDINAL.match(token)
    if ordinal and int(ordinal.group(1)) < len(ORDINAL_WORDS):
        return ORDINAL_WORDS[int(ordinal.group(1))]
    if token.isdigit() and int(token) < len(CARDINAL_WORDS):
        return CARDINAL_WORDS[int(token)]
    return token


def sentence_vector(text: str, word_vectors: "WordVectors",
                    vocabulary: Collection[str] | None = None) -> SentenceVector:
    """§2.2.3.2: the sentence vector of one simple instruction; unknown words are skipped and
    counted (word_vectors.oov_counts). Beyond the seed, with a `vocabulary` (phrase_vocabulary)
    words outside it are skipped too ("take a lift turn": speech recognition's "lift" for
    "left" is a GloVe word the phrase sets never use). InstructionError if no word is left."""
    tokens = [word for token in tokenise(text)
              for word in compound_words(token, word_vectors, vocabulary)]
    if not tokens:
        raise InstructionError(f"simple instruction {text!r} has no words")
    outside = [t for t in tokens if vocabulary is not None and t not in vocabulary]
    vectors, unknown = word_vectors.lookup([t for t in tokens if t not in outside])
    skipped = [t for t in tokens if t in outside or t in unknown]
    if vectors.shape[0] == 0:
        where = f"{word_vectors.source}" + (" and the phrase sets" if vocabulary else "")
        raise InstructionError(f"no word of {text!r} is in the vocabulary of {where} "
                               f"(unknown: {', '.join(skipped)})")
    return SentenceVector(text=text, tokens=tokens, vectors=vectors, oov=skipped)


def compound_words(token: str, word_vectors: "WordVectors",
                   vocabulary: Collection[str] | None = None) -> list[str]:
    """A hyphenated token that is not a known word as its parts ("about-face" -> "about",
    "face"); any other token as it is."""
    known = token in word_vectors and (vocabulary is None or token in vocabulary)
    if "-" not in token or known:
        return [token]
    return [part for part in token.split("-") if part]


def phrase_vocabulary(path: str | os.PathLike[str]) -> frozenset[str]:
    """Every word of a phrase-set file (config/semnav_phrases.yaml: every set and split, "{dir}"
    as right and left), as `tokenise` gives them -> frozenset. InstructionError naming the file
    when it cannot be read."""
    import yaml
    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as error:
        raise InstructionError(f"phrase vocabulary {path}: {error}") from None
    words: set[str] = set()
    stack: list[Any] = [data]    # parsed YAML: strings, mappings and lists of them
    while stack:
        value = stack.pop()
        if isinstance(value, str):
            for side in ("right", "left"):
                words.update(tokenise(value.replace("{dir}", side)))
        elif isinstance(value, dict):
            stack.extend(value.values())
        elif isinstance(value, list):
            stack.extend(value)
    if not words:
        raise InstructionError(f"phrase vocabulary {path}: no phrases in it")
    return frozenset(words)


def convert_instruction(sentence: str, word_vectors: "WordVectors") -> list[SentenceVector]:
    """Split a sentence and convert each simple instruction: list of SentenceVector, in order."""
    return [sentence_vector(part, word_vectors) for part in split_instruction(sentence)]


# ---------------------------------------------------------------- counting one side or both
# Beyond the seed: "the second right" names the second branch on the right, "the second corner"
# the second corner over both sides. A side word used as a noun after an ordinal ("the second
# right", "the third left-hand turning"), an ordinal thing on a side ("the second opening on your
# right", "the second on the right") and counting by passing a side's branches ("skip the first
# right", "pass two lefts", "let one left go by", "not this right but the next one", "don't take
# the first right") count one side; everything else counts corners ("the second right-hand
# corner" too). Tokens as `tokenise` gives them.
HAND = r"(?:-hand| hand)?s?"                 # "right-hand", "right hand", "rights"
SIDE_NOUNS = rf"(?:right|left){HAND}"
ORDINALS = r"(?:second|third)"
SIDE_THINGS = (r"(?:turn|turns|turning|turnings|opening|openings|branch|branches|exit|exits|"
               r"hallway|hallways|corridor|corridors|hall|passage|way|one|street|road)")
CORNER_NOUNS = r"(?:corner|corners|intersection|intersections|junction|junctions|crossing|" \
               r"crossings|crossroad|crossroads)"
# a side noun not naming a corner ("the second right-hand corner" counts corners)
SIDE_NOT_CORNER = rf"(?:right|left)(?!{HAND} {CORNER_NOUNS}\b){HAND}\b"
ONE_SIDE_COUNTS = re.compile(
    rf"\b{ORDINALS} {SIDE_NOT_CORNER}"
    rf"|\b{ORDINALS} (?:{SIDE_THINGS} )?(?:on|to) (?:the|your|its) {SIDE_NOUNS}\b"
    rf"|\b(?:skip|skipping|pass|passing|miss|missing|ignore|ignoring|past|after) (?:the )?"
    rf"(?:first(?: two)?|one|two) {SIDE_NOT_CORNER}"
    rf"|\blet (?:the )?(?:first|one|two) {SIDE_NOUNS} (?:go|pass)\b"
    rf"|\b(?:not|n't)(?: take| use)? (?:this|the (?:next|first)(?: two)?) {SIDE_NOT_CORNER}")


def counting_mode(text: str, label: int | None = None) -> str:
    """COUNT_SIDE when the simple instruction `text` counts the branches on one side (module
    comment above), else COUNT_CORNERS; always COUNT_CORNERS for a class `label` that counts
    nothing (not 5-8)."""
    if label is not None and label not in COUNTING_IDS:
        return COUNT_CORNERS
    return COUNT_SIDE if ONE_SIDE_COUNTS.search(" ".join(tokenise(text))) else COUNT_CORNERS


# ---------------------------------------------------------------- directions the robot can follow
# Beyond the seed: a sentence is refused before the robot moves when it asks for more than the ten
# instruction classes can do, or is not English. Without these checks "turn left at the 99th
# corner" drove (GloVe knows "99th"; LSTM_w classed it as a third-corner turn) and so did a
# German sentence (GloVe 6B holds many non-English words, so no word was "unknown").
# MAX_CORNER (instruction_classes): Table 3.1-1 counts corners up to "the third corner" (7, 8)
CORNER_WORDS = frozenset((
    "corner", "corners", "intersection", "intersections", "crossroad", "crossroads", "crossing",
    "crossings", "turning", "turnings", "junction", "junctions", "turn", "turns", "left", "right",
    "lefts", "rights", "opening", "openings", "branch", "branches", "hallway", "hallways",
    "corridor", "corridors"))
COUNT_PAST = frozenset(("after", "past", "beyond"))   # "after the second corner" = the third
MEASURES = frozenset(("m", "metre", "metres", "meter", "meters", "foot", "feet", "yard", "yards",
                      "step", "steps", "second", "seconds", "minute", "minutes", "times"))
UNITS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine", "ten",
         "eleven", "twelve", "thirteen", "fourteen", "fifteen", "sixteen", "seventeen",
         "eighteen", "nineteen")
UNIT_ORDINALS = ("zeroth", "first", "second", "third", "fourth", "fifth", "sixth", "seventh",
                 "eighth", "ninth", "tenth", "eleventh", "twelfth", "thirteenth", "fourteenth",
                 "fifteenth", "sixteenth", "seventeenth", "eighteenth", "nineteenth")
TENS = {"twenty": 20, "thirty": 30, "forty": 40, "fifty": 50, "sixty": 60, "seventy": 70,
        "eighty": 80, "ninety": 90}
TENS_ORDINALS = {"twentieth": 20, "thirtieth": 30, "fortieth": 40, "fiftieth": 50,
                 "sixtieth": 60, "seventieth": 70, "eightieth": 80, "ninetieth": 90}
LARGE = {"hundred": 100, "hundredth": 100, "thousand": 1000, "thousandth": 1000,
         "million": 10 ** 6, "millionth": 10 ** 6}
DIGIT_ORDINAL = re.compile(r"^(\d+)(?:st|nd|rd|th)$")
# GloVe 6B's most frequent words include the function words of other languages (names and
# quotes in its news and encyclopaedia text: "la", "el", "und", "het" are among its 35,000 most
# frequent). These, from German, French, Spanish, Italian, Dutch and Portuguese directions, are
# not counted as English: their function words and their words for left, right, straight on,
# end, corner, corridor, please, go and turn. Words English uses too ("a", "an", "in", "am",
# "den", "die", "final", "fine", "coin", "pour", "loop", "gang", "links", "no", "as") are left
# out.
FOREIGN_WORDS = frozenset("""
der das und zum zur bis dann dem des ein eine einen nach mit bitte geh gehe ist nicht zu im
auf biege nimm fahr rechts ecke flur entlang kreuzung bleib
le la les du et au aux puis jusqu tout droit droite gauche va vers dans sur avec plaît une est
prends tourne avance couloir arrête toi deuxième troisième
el los las y del al hasta hacia por gira derecha izquierda luego sigue una para camina pasillo
esquina toma tercera segunda allí espera recto
il lo gli della alla fino poi e destra sinistra favore vai di da prendi terza secondo angolo
cammina lungo corridoio fermati dritto
het een en tot naar bij ga sla neem hoek derde tweede alsjeblieft wacht daar rechtdoor einde
até depois vire direita esquerda na pelo siga frente fim ande pegue terceira à
""".split())


@dataclass(frozen=True)
class FollowableConfig:
    """When a sentence counts as English (the rule of `english_fraction`)."""

    common_words: int = 30000          # a word is common English when it is among this many most
                                       # frequent words of GloVe 6B (its vocabulary is ordered
                                       # by frequency: row 0 is "the")
    min_english_fraction: float = 0.6  # fewer common English words than this share: refused


class UnfollowableInstruction(InstructionError):
    """A sentence the robot must not try: str() says why in full, `spoken` says it to a person."""

    def __init__(self, reason: str, spoken: str) -> None:
        super().__init__(reason)
        self.spoken = spoken


def number_value(token: str) -> tuple[int, bool] | None:
    """(value, is_ordinal) of a number token ("99th", "4", "fourth", "twenty-first",
    "hundredth"), else None."""
    digits = DIGIT_ORDINAL.match(token)
    if digits:
        return int(digits.group(1)), True
    if token.isdigit():
        return int(token), False
    total, ordinal = 0, False
    for part in token.split("-"):
        if part in UNITS:
            total += UNITS.index(part)
        elif part in UNIT_ORDINALS:
            total, ordinal = total + UNIT_ORDINALS.index(part), True
        elif part in TENS or part in TENS_ORDINALS:
            total += TENS.get(part) or TENS_ORDINALS[part]
            ordinal = part in TENS_ORDINALS
        elif part in LARGE:
            total, ordinal = max(total, 1) * LARGE[part], part.endswith("th")
        else:
            return None
    return total, ordinal


def ordinal_text(number: int) -> str:
    """1 -> "1st", 12 -> "12th", 23 -> "23rd", 99 -> "99th"."""
    if 10 <= number % 100 <= 20:
        return f"{number}th"
    return f"{number}{ {1: 'st', 2: 'nd', 3: 'rd'}.get(number % 10, 'th')}"


def corners_asked(text: str) -> list[int]:
    """The corner numbers one simple instruction counts to: a number before a corner word
    ("the 99th corner", "five corners down", "the fourth left") or after "corner" ("corner
    number four", "corner three"), one more after "after" / "past" ("after the third corner" is
    the fourth); a cardinal before a measure ("the corner 5 metres ahead") is a distance."""
    tokens = TOKEN.findall(text.lower())
    asked: list[int] = []
    for i, token in enumerate(tokens):
        value = number_value(token)
        if value is None:
            continue
        before, after = tokens[max(0, i - 2):i], tokens[i + 1:i + 3]
        if after[:1] and after[0] in MEASURES and not value[1]:
            continue                      # "the corner 5 metres ahead": a distance
        if not (CORNER_WORDS & set(after) or before[-1:] == ["corner"]
                or before[-2:] == ["corner", "number"]):
            continue
        asked.append(value[0] + (1 if COUNT_PAST & set(before) else 0))
    return asked


def english_fraction(sentence: str, word_vectors: "WordVectors",
                     config: FollowableConfig | None = None) -> tuple[int, int]:
    """(common, words): how many of the sentence's words (letters only, any alphabet; numbers
    left out) are common English words: among the `common_words` most frequent of the word
    vectors' vocabulary (GloVe files list words by frequency) and not in FOREIGN_WORDS."""
    config = config or FollowableConfig()
    words = [w for w in re.findall(r"\w+", sentence.lower())
             if not any(c.isdigit() or c == "_" for c in w)]
    common = sum(1 for w in words if w not in FOREIGN_WORDS and
                 word_vectors.index.get(w, config.common_words) < config.common_words)
    return common, len(words)


def check_followable(sentence: str, word_vectors: "WordVectors | None" = None,
                     config: FollowableConfig | None = None) -> None:
    """Refuse (UnfollowableInstruction) a sentence the robot must not try to follow:

    - with `word_vectors`, a sentence of which fewer than `min_english_fraction` of the words are
      common English words (english_fraction: words of any alphabet count, so Chinese is refused
      here; a sentence without words is left to split_instruction, which refuses it), unless a
      single word is uncommon beside a common one ("veer right": "veer" is GloVe's 30,834th);
    - a corner beyond MAX_CORNER, or before the first (Table 3.1-1 counts the first to the
      third corner), in any simple instruction (corners_asked).
    """
    config = config or FollowableConfig()
    if word_vectors is not None:
        common, words = english_fraction(sentence, word_vectors, config)
        if (words and common < config.min_english_fraction * words
                and (common == 0 or words - common >= 2)):
            raise UnfollowableInstruction(
                f"only {common} of its {words} words are common English words (among the "
                f"{config.common_words} most frequent of {word_vectors.source}), fewer than "
                f"{config.min_english_fraction:.0%}: not English, or not directions",
                "Sorry, I can only follow directions in English. I am staying here.")
    for part in split_instruction(sentence):
        for corner in corners_asked(part):
            if not 1 <= corner <= MAX_CORNER:
                raise UnfollowableInstruction(
                    f"{part!r} asks for the {ordinal_text(corner)} corner; the instruction "
                    f"classes count corners from the 1st to the {ordinal_text(MAX_CORNER)}",
                    f"Sorry, I can only count corners up to the {ORDINAL_WORDS[MAX_CORNER]} "
                    f"one, and you asked for the {ordinal_text(corner)}. I am staying here.")
