"""Instruction layer, conversion stage (thesis 002 §2.2.3.2 and §3.1): sentence -> simple
instructions -> tokens -> sentence vectors (one GloVe vector per word)."""
import re
from dataclasses import dataclass, field

import numpy as np

# §3.1: "we simply use punctuation marks to split sentences into simple instruction".
PUNCTUATION = re.compile(r"[.,;:!?\n]+")
# Spoken text (speech recognition) has no punctuation: "then" / "and then" also end an instruction.
# "and" alone never splits: "go straight to the end and turn right" is one instruction (class 9).
THEN = re.compile(r"\b(?:and\s+)?then\b")
LEADING_CONNECTIVE = re.compile(r"^(?:and\s+then|then|and)\b\s*")
TRAILING_CONNECTIVE = re.compile(r"\s*\b(?:and|and\s+then|then)$")
# Lower-case tokens as in GloVe 6B: words, numbers, clitics ('s, 'd) and n't split off.
TOKEN = re.compile(r"[a-z0-9]+(?=n't)|n't|'[a-z]+|[a-z0-9]+(?:-[a-z0-9]+)*")
# Numerals as words: typed and transcribed instructions write "2nd corner" or "2 corners", the
# phrase sets (and so LSTM_w) know "second" and "two"; GloVe puts "2nd" about as near "third"
# (cosine 0.58) as "second" (0.60).
ORDINAL = re.compile(r"^(\d+)(?:st|nd|rd|th)$")
ORDINAL_WORDS = ("zeroth", "first", "second", "third", "fourth", "fifth", "sixth", "seventh",
                 "eighth", "ninth", "tenth")
CARDINAL_WORDS = ("zero", "one", "two", "three", "four", "five", "six", "seven", "eight",
                  "nine", "ten")


class InstructionError(ValueError):
    """An instruction that cannot be turned into sentence vectors; the message says why."""


@dataclass
class SentenceVector:
    """The word vectors of one simple instruction (§2.2.3.2) and what was left out."""

    text: str                       # the simple instruction
    tokens: list                    # its lower-case tokens
    vectors: np.ndarray             # float32 (n_known_tokens, dim), in token order
    oov: list = field(default_factory=list)  # tokens without a word vector (skipped)


def split_instruction(sentence):
    """§3.1: split a sentence into simple instructions at punctuation and at "(and) then"."""
    if not isinstance(sentence, str):
        raise InstructionError(f"instruction must be text, got {type(sentence).__name__}")
    parts = []
    for clause in PUNCTUATION.split(sentence.lower()):
        for piece in THEN.split(clause):
            piece = " ".join(piece.split())
            piece = TRAILING_CONNECTIVE.sub("", LEADING_CONNECTIVE.sub("", piece))
            if TOKEN.search(piece):
                parts.append(piece)
    if not parts:
        raise InstructionError(f"instruction {sentence!r} has no words")
    return parts


def tokenise(text):
    """Lower-case word tokens of one simple instruction, numerals up to ten as words."""
    return [numeral_as_word(token) for token in TOKEN.findall(text.lower())]


def numeral_as_word(token):
    """"2nd" -> "second", "3" -> "three" (0 to 10); any other token unchanged."""
    ordinal = ORDINAL.match(token)
    if ordinal and int(ordinal.group(1)) < len(ORDINAL_WORDS):
        return ORDINAL_WORDS[int(ordinal.group(1))]
    if token.isdigit() and int(token) < len(CARDINAL_WORDS):
        return CARDINAL_WORDS[int(token)]
    return token


def sentence_vector(text, word_vectors):
    """§2.2.3.2: the sentence vector of one simple instruction; unknown words are skipped and
    counted (word_vectors.oov_counts). InstructionError if no word is known."""
    tokens = tokenise(text)
    if not tokens:
        raise InstructionError(f"simple instruction {text!r} has no words")
    vectors, unknown = word_vectors.lookup(tokens)
    if vectors.shape[0] == 0:
        raise InstructionError(f"no word of {text!r} is in the vocabulary of "
                               f"{word_vectors.source} (unknown: {', '.join(unknown)})")
    return SentenceVector(text=text, tokens=tokens, vectors=vectors, oov=unknown)


def convert_instruction(sentence, word_vectors):
    """Split a sentence and convert each simple instruction: list of SentenceVector, in order."""
    return [sentence_vector(part, word_vectors) for part in split_instruction(sentence)]
