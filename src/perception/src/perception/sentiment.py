"""Sentence sentiment with VADER (thesis 000 §3.1.3, §3.3): compound score and its label."""
import re
from collections.abc import Collection
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


def sentiment_label(compound: float, threshold: float = SentimentConfig.threshold) -> str:
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


def mood_text(text: str, ignored_words: Collection[str]) -> str:
    """The text VADER should score: `text` without words that only frame a request.

    Our addition to §3.3: request verbs such as "cheer", "help" or "play" are positive in VADER's
    lexicon, which pulls every request towards positive whatever the speaker's mood.
    """
    if not ignored_words:
        return text
    pattern = r"\b(?:" + "|".join(re.escape(w) for w in sorted(ignored_words)) + r")\b"
    return re.sub(pattern, "", text, flags=re.IGNORECASE)


class SentimentAnalyzer:
    """VADER with its bundled lexicon (no network): text -> Sentiment."""

    def __init__(self, config: SentimentConfig = SentimentConfig()) -> None:
        self.config = config
        self._vader = SentimentIntensityAnalyzer()  # reads the lexicon shipped in the package

    def analyse(self, text: str) -> Sentiment:
        compound = self._vader.polarity_scores(text)["compound"]
        return Sentiment(compound=compound, label=sentiment_label(compound, self.config.threshold))
