"""Misheard words: the phrase-set words that a word outside the phrase sets may stand for.

Speech recognition turns a word of a spoken direction into another English word that sounds
alike ("left" heard as "lift", "right" as "light"). The follower skips a word outside the phrase
sets; before that, it tries the phrase-set words a few letter edits away in its place
(DirectionFollower.start). Beyond the seed.
"""
import itertools
from collections.abc import Collection, Iterable, Sequence

MIN_LENGTH = 3          # shorter words ("a", "to") are too close to too many others
MAX_READINGS = 32       # combinations of replacements tried for one simple instruction
# Words spelt unlike a phrase-set word but said (nearly) the same, which Whisper writes for it
# and letter edits do not reach or reach wrongly ("go write": "write" is three edits from
# "right"; "ride" is one from "side"). A reading with them is tried first (`reads_homophones`).
HOMOPHONES = {"write": "right", "rite": "right", "wright": "right", "ride": "right",
              "riot": "right"}


def edit_distance(a: str, b: str) -> int:
    """Levenshtein distance: the fewest insertions, deletions and substitutions of letters that
    turn `a` into `b`."""
    previous = list(range(len(b) + 1))
    for i, letter in enumerate(a, 1):
        current = [i]
        for j, other in enumerate(b, 1):
            current.append(min(previous[j] + 1, current[j - 1] + 1,
                               previous[j - 1] + (letter != other)))
        previous = current
    return previous[-1]


def sound_alikes(word: str, vocabulary: Collection[str], max_edits: int = 1) -> list[str]:
    """The words of `vocabulary` `word` may stand for: its homophone (HOMOPHONES) first, then
    those at most `max_edits` letter edits away (not `word` itself), nearest first, then
    alphabetical; none for a word shorter than MIN_LENGTH."""
    if len(word) < MIN_LENGTH or max_edits < 1:
        return []
    same = [HOMOPHONES[word]] if HOMOPHONES.get(word) in vocabulary else []
    near = [(edit_distance(word, other), other) for other in vocabulary
            if other != word and other not in same and len(other) >= MIN_LENGTH
            and abs(len(other) - len(word)) <= max_edits]
    return same + [other for distance, other in sorted(near) if distance <= max_edits]


def readings(tokens: Sequence[str], skipped: Iterable[str], vocabulary: Collection[str],
             max_edits: int = 1) -> list[tuple[list[str], tuple[tuple[str, str], ...]]]:
    """Other readings of a simple instruction's `tokens` in which skipped words are replaced by
    their sound-alikes: [(tokens, ((heard, read as), ...))], one replacement first, then two,
    and so on, at most MAX_READINGS; a word with no sound-alike stays as it is."""
    options = {word: sound_alikes(word, vocabulary, max_edits) for word in dict.fromkeys(skipped)}
    words = [word for word, alikes in options.items() if alikes]
    found: list[tuple[list[str], tuple[tuple[str, str], ...]]] = []
    for count in range(1, len(words) + 1):
        for replaced in itertools.combinations(words, count):
            for choice in itertools.product(*[options[word] for word in replaced]):
                corrections = tuple(zip(replaced, choice))
                replace = dict(corrections)
                found.append(([replace.get(token, token) for token in tokens], corrections))
                if len(found) == MAX_READINGS:
                    return found
    return found


def reads_homophones(corrections: Iterable[tuple[str, str]], skipped: Iterable[str]) -> bool:
    """Whether a reading reads every skipped word that has a homophone (HOMOPHONES) as that
    homophone, whatever else it replaces (vacuously true when none has one)."""
    replaced = dict(corrections)
    return all(replaced.get(word) == HOMOPHONES[word] for word in skipped if word in HOMOPHONES)


def read_as(corrections: Iterable[tuple[str, str]]) -> str:
    """What was read as what, for a log line: "'lift' as 'left', ..." ("" for none)."""
    return ", ".join(f"{heard!r} as {word!r}" for heard, word in corrections)
