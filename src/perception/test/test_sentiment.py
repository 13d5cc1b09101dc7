"""VADER sentiment and its ±0.05 labels (thesis 000 §3.3)."""
import math
import socket

import pytest

from perception.sentiment import (NEGATIVE, NEUTRAL, POSITIVE, SentimentAnalyzer, mood_text,
                                  sentiment_label)


def vader_normalise(score, alpha=15.0):
    """VADER's compound: x / sqrt(x^2 + alpha), computed here independently of the package."""
    return score / math.sqrt(score * score + alpha)


@pytest.mark.parametrize("compound, label", [
    (0.05, POSITIVE), (0.0499, NEUTRAL), (0.0, NEUTRAL), (-0.0499, NEUTRAL), (-0.05, NEGATIVE),
    (0.9, POSITIVE), (-1.0, NEGATIVE)])
def test_label_thresholds_are_plus_minus_0_05(compound, label):
    assert sentiment_label(compound) == label


def test_label_rejects_score_outside_minus_one_one():
    with pytest.raises(ValueError, match="compound"):
        sentiment_label(1.5)


def test_seed_example_feel_bad_is_negative(analyser):
    # "bad" is -2.5 in VADER's lexicon, the only rated word of the sentence.
    result = analyser.analyse("Chat with me, I feel bad.")
    assert result.compound == pytest.approx(vader_normalise(-2.5), abs=1e-4)  # -0.5423
    assert result.label == NEGATIVE


def test_physical_complaint_scores_neutral(analyser):
    # The reason physical terms must set the priority themselves (issue 8).
    result = analyser.analyse("I have a headache and fever")
    assert result.compound == 0.0
    assert result.label == NEUTRAL


def test_vader_runs_without_network(monkeypatch):
    def no_network(*args, **kwargs):
        raise OSError("network used")

    monkeypatch.setattr(socket, "socket", no_network)
    monkeypatch.setattr(socket, "create_connection", no_network)
    analyser = SentimentAnalyzer()
    assert analyser.analyse("I love this song").label == POSITIVE


def test_mood_text_drops_request_words_only():
    text = "Please cheer me up, I failed my exam."
    assert mood_text(text, {"please", "cheer"}) == "  me up, I failed my exam."
    assert mood_text("The caregiver cares", {"care"}) == "The caregiver cares"
    assert mood_text(text, frozenset()) == text


def test_masking_request_words_reveals_the_mood(analyser):
    text = "Please cheer me up, I failed my exam."
    # Plain VADER: please +1.3, cheer +2.3, failed -2.3 -> positive despite the failed exam.
    assert analyser.analyse(text).label == POSITIVE
    masked = analyser.analyse(mood_text(text, {"please", "cheer"}))
    assert masked.compound == pytest.approx(vader_normalise(-2.3), abs=1e-4)  # -0.5106
    assert masked.label == NEGATIVE
