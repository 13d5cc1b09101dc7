"""Word error rate of recognised speech against the sentence that was spoken."""
import re

_WORD = re.compile(r"[a-z0-9]+(?:'[a-z]+)?")


def normalise_words(text):
    """Lowercase words without punctuation ("Chat with me, I feel bad." -> chat with me i feel
    bad); typographic apostrophes count as plain ones."""
    return _WORD.findall(text.lower().replace("’", "'"))


def word_edit_distance(reference, hypothesis):
    """Levenshtein distance between two word lists (substitutions, deletions, insertions)."""
    previous = list(range(len(hypothesis) + 1))
    for i, ref_word in enumerate(reference, start=1):
        current = [i]
        for j, hyp_word in enumerate(hypothesis, start=1):
            current.append(min(previous[j] + 1, current[j - 1] + 1,
                               previous[j - 1] + (ref_word != hyp_word)))
        previous = current
    return previous[-1]


def word_error_rate(references, hypotheses):
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
