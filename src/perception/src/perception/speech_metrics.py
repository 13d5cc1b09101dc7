"""Word error rate of recognised speech against the sentence that was spoken."""
import re
from collections.abc import Sequence

_WORD = re.compile(r"[a-z0-9]+(?:'[a-z]+)?")


def normalise_words(text: str) -> list[str]:
    """Lowercase words without punctuation ("Chat with me, I feel bad." -> chat with me i feel
    bad); typographic apostrophes count as plain ones."""
    return _WORD.findall(text.lower().replace("’", "'"))


def word_edit_distance(reference: Sequence[str], hypothesis: Sequence[str]) -> int:
    """Levenshtein distance between two word lists (substitutions, deletions, insertions): the
    edits of their word_alignment."""
    return sum(said != heard for said, heard in word_alignment(reference, hypothesis))


def word_error_rate(references: Sequence[str], hypotheses: Sequence[str]) -> float:
    """Corpus WER: total word edits / total reference words, over paired sentences."""
    if len(references) != len(hypotheses):
        raise ValueError(f"{len(references)} references but {len(hypotheses)} hypotheses")
    edits = words = 0
    for reference, hypothesis in zip(references, hypotheses):
        ref = normalise_words(reference)
        edits += word_edit_distance(ref, normalise_words(hypothesis))
        words += len(ref)
    if words == 0:
        raise ValueError("references hold no words")
    return edits / words


def word_alignment(reference: Sequence[str],
                   hypothesis: Sequence[str]) -> list[tuple[str | None, str | None]]:
    """A minimal-edit alignment of two word lists -> [(reference word or None, hypothesis word
    or None)]: equal pairs, substitutions, deletions (None heard) and insertions (None said).
    Minimal: its edits are the Levenshtein distance; ties prefer a substitution, then a
    deletion."""
    rows, cols = len(reference) + 1, len(hypothesis) + 1
    cost = [[0] * cols for _ in range(rows)]
    for i in range(rows):
        cost[i][0] = i
    for j in range(cols):
        cost[0][j] = j
    for i in range(1, rows):
        for j in range(1, cols):
            cost[i][j] = min(cost[i - 1][j] + 1, cost[i][j - 1] + 1,
                             cost[i - 1][j - 1] + (reference[i - 1] != hypothesis[j - 1]))
    pairs: list[tuple[str | None, str | None]] = []
    i, j = len(reference), len(hypothesis)
    while i or j:
        if i and j and cost[i][j] == cost[i - 1][j - 1] + (reference[i - 1] != hypothesis[j - 1]):
            pairs.append((reference[i - 1], hypothesis[j - 1]))
            i, j = i - 1, j - 1
        elif i and cost[i][j] == cost[i - 1][j] + 1:
            pairs.append((reference[i - 1], None))
            i -= 1
        else:
            pairs.append((None, hypothesis[j - 1]))
            j -= 1
    return pairs[::-1]


def misheard_words(reference: str, hypothesis: str) -> list[tuple[str | None, str | None]]:
    """The word edits of one transcript: [(said, heard)] with None for a word dropped (heard) or
    added (said), both normalised (normalise_words)."""
    return [(said, heard) for said, heard in word_alignment(normalise_words(reference),
                                                           normalise_words(hypothesis))
            if said != heard]
