"""Decoding held to a command vocabulary, beside Whisper's free decoding (beyond both seeds).

A robot that takes a known set of commands (semantic_nav's directions) can tell the recogniser
which words it knows, as command-and-control recognisers do with a grammar. Whisper has no
grammar, but its decoder can be barred from every text token that no word of the vocabulary uses
(`suppressed_outside`): the held decoding then spells only those words' pieces. Speech that is
not in the vocabulary ("what's for dinner?") would still come out as vocabulary words, so the
held reading is taken only when Whisper scores it close to its free reading (`choose_reading`):
barred tokens leave the rest of each step's probability to the allowed ones, so a held reading
of in-vocabulary speech scores about as high as the free one or higher, and one of other speech
mostly far lower.
"""
import math
import re
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

WORD = re.compile(r"[a-z]+(?:'[a-z]+)?")
PLACEHOLDER = re.compile(r"\{[^{}]*\}")   # "{dir}" in a phrase template: no word of its own
#                                          ("{dir}s" leaves "s", so "lefts" can be spelt)
# Written forms Whisper gives a sentence besides its words: kept open in the held decoding.
PUNCTUATION = (".", ",", "?", "!", "'", " '", "-")


class VocabularyError(ValueError):
    """A vocabulary file that cannot be read or holds no word."""


@dataclass(frozen=True)
class Decoding:
    text: str         # the decoded sentence
    log_prob: float   # Whisper's log-probability of its tokens (window_log_prob) [nats]


class Segment(Protocol):
    """What window_log_prob reads of a faster-whisper segment."""

    @property
    def seek(self) -> int: ...          # start of its 30-s window [frames]
    @property
    def avg_logprob(self) -> float: ...
    @property
    def tokens(self) -> list[int]: ...


def vocabulary_path(path: str | Path, config_dir: str | Path | None = None) -> Path:
    """The file of a vocabulary setting: an absolute path (or one from ~) as it is, a relative
    one in tamp_resources' config folder (`config_dir`, found with rospkg when None), so that
    one setting reads the same for the STT node and for an evaluation. VocabularyError when
    that folder cannot be found."""
    path = Path(path).expanduser()
    if path.is_absolute():
        return path
    if config_dir is None:
        from tamp_resources import resource   # rospkg: only for a relative setting
        try:
            config_dir = resource("config")
        except RuntimeError as error:
            raise VocabularyError(f"STT vocabulary {path}: {error}") from None
    return Path(config_dir) / path


def _strings(data: object) -> Iterator[str]:
    """Every string of parsed YAML, mapping keys left out."""
    if isinstance(data, str):
        yield data
    elif isinstance(data, dict):
        for value in data.values():
            yield from _strings(value)
    elif isinstance(data, list):
        for item in data:
            yield from _strings(item)


def vocabulary_words(path: str | Path) -> frozenset[str]:
    """The words of a vocabulary file, lower-cased (letters with at most one apostrophe inside)
    -> frozenset: of a YAML file (.yaml, .yml; e.g. config/semnav_phrases.yaml) its string
    values, without mapping keys, comments and {placeholders}; of any other file its whole
    text. VocabularyError naming the file when it cannot be read or holds no word."""
    import yaml
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
        texts = (list(_strings(yaml.safe_load(text))) if path.suffix in (".yaml", ".yml")
                 else [text])
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as error:
        raise VocabularyError(f"STT vocabulary {path}: {error}") from None
    words = frozenset(word for text in texts
                      for word in WORD.findall(PLACEHOLDER.sub("", text.lower())))
    if not words:
        raise VocabularyError(f"STT vocabulary {path} holds no word")
    return words


def suppressed_outside(encode: Callable[[str], Iterable[int]], end_of_text: int,
                       words: Iterable[str], barred: Iterable[int] = ()) -> list[int]:
    """Token ids below `end_of_text` (Whisper's text tokens) that no form of `words` uses: the
    word with and without a leading space, lower-case and capitalised, plus PUNCTUATION; and
    the `barred` ones (Whisper's non-speech tokens, which its free decoding bars too).
    `encode`: text -> token ids (Whisper's tokenizer). -> sorted list, for suppress_tokens."""
    allowed: set[int] = set()
    for word in words:
        for form in (word, word.capitalize()):
            allowed.update(encode(" " + form))
            allowed.update(encode(form))
    for mark in PUNCTUATION:
        allowed.update(encode(mark))
    allowed.difference_update(barred)
    return [token for token in range(end_of_text) if token not in allowed]


def window_log_prob(segments: Iterable[Segment]) -> float:
    """Whisper's log-probability of a decoding's tokens from faster-whisper's segments: every
    segment cut from one 30-s window (same `seek`) carries that window's avg_logprob, its summed
    log-probability over the window's tokens and end divided by their count."""
    windows: dict[int, tuple[float, int]] = {}
    for segment in segments:
        average, tokens = windows.get(segment.seek, (segment.avg_logprob, 0))
        windows[segment.seek] = (average, tokens + len(segment.tokens))
    return sum(average * (tokens + 1) for average, tokens in windows.values())


def choose_reading(free: Decoding, held: Decoding | None, margin: float) -> tuple[str, bool]:
    """The text to publish: the held decoding's when it exists (it is None when it got stuck
    repeating) and scores at most `margin` nats below the free one, else the free decoding's.
    -> (text, True when the held reading was taken)."""
    if not (math.isfinite(margin) and margin >= 0):
        raise ValueError(f"margin must be a finite number >= 0; got {margin}")
    if held is not None and held.text and held.log_prob >= free.log_prob - margin:
        return held.text, True
    return free.text, False
