"""Misheard words: the phrase-set words that a word outside the phrase sets may stand for.

Speech recognition turns a word of a spoken direction into another English word that sounds
alike ("left" heard as "lift", "right" as "light"). The follower skips a word outside the phrase
sets; when the rest of the instruction does not read with confidence, it tries the phrase-set
words a few letter edits away instead (DirectionFollower.start). Beyond the seed.
"""
import itertools

MIN_LENGTH = 3          # shorter words ("a", "to") are too close to too many others
MAX_READINGS = 32       # combinations of replacements tried for one simple instruction


def edit_distance(a, b):
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


def sound_alikes(word, vocabulary, max_edits=1):
    """The words of `vocabulary` at most `max_edits` letter edits from `word` (not `word`
    itself), nearest first, then alphabetical; none for a word shorter than MIN_LENGTH."""
    if len(word) < MIN_LENGTH or max_edits < 1:
        return []
    near = [(edit_distance(word, other), other) for other in vocabulary
            if other != word and len(other) >= MIN_LENGTH
            and abs(len(other) - len(word)) <= max_edits]
    return [other for distance, other in sorted(near) if distance <= max_edits]


def readings(tokens, skipped, vocabulary, max_edits=1):
    """Other readings of a simple instruction's `tokens` in which skipped words are replaced by
    their sound-alikes: [(tokens, ((heard, read as), ...))], at most MAX_READINGS, each with at
    least one replacement; a word with no sound-alike stays as it is."""
    options = {word: sound_alikes(word, vocabulary, max_edits) for word in dict.fromkeys(skipped)}
    words = [word for word, alikes in options.items() if alikes]
    found = []
    for choice in itertools.product(*[[None] + options[word] for word in words]):
        corrections = tuple((word, alike) for word, alike in zip(words, choice) if alike)
        if not corrections:
            continue
        replace = dict(corrections)
        found.append(([replace.get(token, token) for token in tokens], corrections))
        if len(found) == MAX_READINGS:
            break
    return found
