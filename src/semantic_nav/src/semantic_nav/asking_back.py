"""Asking back before driving (beyond the seed).

A misread direction sends the robot the wrong way, and a person beside it can put that right in
a second. So when the follower is not sure of what it read, the robot says what it understood
and waits for a yes, a no or the direction again before it drives:

- `unsure_reasons`: a simple instruction Z_w reads with less than `AskConfig.min_confidence`, a
  word read as a sound-alike ("lift" as "left"), a word skipped as unknown;
- `describe` / `question`: the simple instructions in words, with how a counted turn counts
  ("take the second right" counts that side's branches, "turn right at the second corner" the
  corners on both sides), e.g. "I understood: go straight to the end, then take the second
  left. Shall I go? Please say yes or no.";
- `read_answer`: an utterance that is only a yes or a no (with filler words) -> YES / NO; any
  other utterance is a new direction and replaces the one asked about.

A "no" or no answer within `AskConfig.answer_timeout` never drives (follow_session).
"""
import re
from collections.abc import Sequence
from dataclasses import dataclass

from semantic_nav.instruction_classes import BACK, COUNT_SIDE, STRAIGHT, get

YES, NO = "yes", "no"
# validation phrasings (scripts/classify_instruction --split validation, 2,000): every one Z_w
# misreads has its largest probability below 0.8; 2.6 % of those it reads right are below 0.9
MIN_CONFIDENCE = 0.9

YES_WORDS = frozenset(("yes", "yeah", "yep", "yup", "correct", "right", "sure", "ok", "okay",
                       "affirmative", "exactly", "absolutely", "go", "ahead", "fine", "good",
                       "please", "do", "true"))
NO_WORDS = frozenset(("no", "nope", "nah", "not", "n't", "wrong", "dont", "stop", "cancel",
                      "negative", "incorrect", "never", "wait"))
FILLER_WORDS = frozenset(("that", "that's", "thats", "it", "is", "s", "'s", "robot", "thank",
                          "thanks", "you", "sir", "of", "course", "oh", "um", "uh", "well",
                          "just", "i", "mean", "a", "the", "so", "all"))
WORD = re.compile(r"[a-z']+|n't")
ORDINAL = {2: "second", 3: "third"}


@dataclass(frozen=True)
class AskConfig:
    """When the robot asks back, and how long it waits for the answer."""

    enabled: bool = True            # false: drive on what was read (the seed's follower)
    min_confidence: float = MIN_CONFIDENCE   # a simple instruction Z_w reads with less: ask
    misheard: bool = True           # a word read as a sound-alike ("lift" as "left"): ask
    unknown: bool = True            # a word skipped as unknown: ask
    answer_timeout: float = 15.0    # [s] no yes or no within this: the robot stays


def unsure_reasons(confidences: Sequence[float], corrections: Sequence[tuple[str, str]],
                   unknown_words: Sequence[str], config: AskConfig) -> list[str]:
    """Why the follower is not sure of a sentence it read: one reason per doubt, [] = sure
    (or asking is off). `confidences`: Z_w's largest probability per simple instruction;
    `corrections`: (heard, read as) of its misheard words; `unknown_words`: words skipped."""
    if not config.enabled:
        return []
    reasons = [f"simple instruction {k + 1} read with confidence {c:.2f} < "
               f"{config.min_confidence}" for k, c in enumerate(confidences)
               if c < config.min_confidence]
    if config.misheard:
        reasons += [f"{heard!r} read as {meant!r}" for heard, meant in corrections]
    if config.unknown and unknown_words:
        reasons.append("unknown word(s) skipped: " + ", ".join(unknown_words))
    return reasons


def describe_instruction(label: int, counting: str | None = None) -> str:
    """One simple instruction of class `label` in words; a counted turn (5-8) as it counts:
    `counting` COUNT_SIDE -> "take the second right", else "turn right at the second corner"."""
    kind = get(label)
    if kind.motion in (STRAIGHT, BACK):
        return {STRAIGHT: "go straight to the end", BACK: "turn around"}[kind.motion]
    if kind.at == "end":
        return f"go straight to the end and turn {kind.side}"
    if kind.corner is None:
        return f"take the first {kind.side}"
    if counting == COUNT_SIDE:
        return f"take the {ORDINAL[kind.corner]} {kind.side}"
    return f"turn {kind.side} at the {ORDINAL[kind.corner]} corner"


def describe(classes: Sequence[int], countings: Sequence[str] | None = None) -> str:
    """A sentence's simple instructions in words, joined by ", then"."""
    modes: list[str | None] = list(countings) if countings else [None] * len(classes)
    return ", then ".join(describe_instruction(label, counting)
                          for label, counting in zip(classes, modes))


def question(classes: Sequence[int], countings: Sequence[str] | None = None) -> str:
    """What the robot says to ask back about the sentence it read as `classes`."""
    return f"I understood: {describe(classes, countings)}. Shall I go? Please say yes or no."


def read_answer(text: str) -> str | None:
    """YES or NO when the utterance `text` is only an answer ("yes", "yes please, go ahead",
    "no, that's wrong"; a no word wins), else None: a direction ("yes, turn left") is not an
    answer but the direction again."""
    words = WORD.findall(text.lower().replace("n't", " n't"))
    if not words or any(w not in YES_WORDS | NO_WORDS | FILLER_WORDS for w in words):
        return None
    if any(w in NO_WORDS for w in words):
        return NO
    return YES if any(w in YES_WORDS for w in words) else None
