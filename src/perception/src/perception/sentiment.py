"""Sentence sentiment with VADER (thesis 000 §3.1.3, §3.3): compound score and its label."""
from dataclasses import dataclass

from vaderSentiment.vaderSentiment import SentimentIntensityAnalyzer

POSITIVE = "positive"
NEUTRAL = "neutral"
NEGATIVE = "negative"


@dataclass(frozen=True)
class SentimentConfig:
    threshold: float = 0.05  # |compound| below this is neutral (§3.3, VADER's own convention)


@dataclass(frozen=True)
class Sentiment:
    compound: float  # VADER compound score in [-1, 1]
    label: str       # POSITIVE, NEUTRAL or NEGATIVE


def sentiment_label(compound, threshold=SentimentConfig.threshold):
    """§3.3: compound >= +threshold is positive, <= -threshold negative, neutral in between.

    The seed cites VADER's thresholds of ±0.05; VADER's documentation counts the boundary value
    itself as positive (>= 0.05) or negative (<= -0.05), and so do we.
    """
    if not -1.0 <= compound <= 1.0:
        raise ValueError(f"VADER compound score must lie in [-1, 1]; got {compound}")
    if compound >= threshold:
        return POSITIVE
    if compound <= -threshold:
        return NEGATIVE
    return NEUTRAL


class SentimentAnalyzer:
    """VADER with its bundled lexicon (no network): text -> Sentiment."""

    def __init__(self, config=SentimentConfig()):
        self.config = config
        self._vader = SentimentIntensityAnalyzer()  # reads the lexicon shipped in the package

    def analyse(self, text):
        compound = self._vader.polarity_scores(text)["compound"]
        return Sentiment(compound=compound, label=sentiment_label(compound, self.config.threshold))
