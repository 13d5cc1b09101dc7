"""Requested robot function, physical terms and target person of one sentence (thesis 000 §3.3,
Fig. 3-15 "Extract Requested Robot Functions"), with the checks that turn bad text away.

Matching is on whole words, case-insensitive; phrases are sequences of words. The keyword tables
come from config/keywords.yaml (see load_keyword_config).
"""
import functools
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import yaml

TARGET = "target"        # served at the location of the named person, else of the speaker
CAREGIVER = "caregiver"  # served at the location of the household's caregiver
PRIORITY_LEVELS = ("physical", "negative", "neutral", "positive")

# Words: runs of letters (any script), with one inner apostrophe ("don't", "bob's").
_WORD = re.compile(r"[^\W\d_]+(?:['’][^\W\d_]+)?")
Phrase = tuple[str, ...]   # lowercase words


class RejectedUtterance(ValueError):
    """Text from outside that cannot become an instruction; the message says why."""


class KeywordConfigError(ValueError):
    """config/keywords.yaml is malformed; the message names the offending entry."""


@dataclass(frozen=True)
class RobotFunction:
    name: str                # e.g. "chat"
    code: int                # tamp_msgs/Instruction.function
    duration_s: int          # time to execute the function at the destination [s]
    served_to: str           # TARGET or CAREGIVER
    keywords: tuple          # phrases (tuples of lowercase words) that request it


@dataclass(frozen=True)
class KeywordConfig:
    functions: dict           # name -> RobotFunction
    physical_function: str    # function requested by a physical term alone
    physical_terms: tuple     # phrases (tuples of lowercase words)
    physical_exceptions: tuple  # phrases inside which a physical term does not count
    negations: tuple          # phrases that cancel a physical term shortly after them
    negation_window: int      # how many words before a physical term a negation reaches [words]
    sentiment_neutral_words: frozenset  # lowercase words left out of the text VADER scores
    chains: dict              # function name -> tuple of follow-up function names
    status_codes: dict        # priority level -> Instruction.status
    caregiver: str            # name of the household member who receives reports
    default_place: str        # graph place used when a person's location is unknown
    person_slot_after: tuple  # phrases after which a capitalised word is read as a name
    max_text_chars: int       # longer text is refused [characters]
    min_english_share: float  # share of known English words below which text is refused
    english_words: frozenset  # lowercase common English words

    def vocabulary(self) -> frozenset[str]:
        """Every lowercase word the configuration knows as English (not a name)."""
        words = set(self.english_words)
        for function in self.functions.values():
            words.update(w for phrase in function.keywords for w in phrase)
        words.update(w for phrase in self.physical_terms for w in phrase)
        words.update(w for phrase in self.person_slot_after for w in phrase)
        words.update(w for phrase in self.physical_exceptions + self.negations for w in phrase)
        words.update(self.sentiment_neutral_words)
        return frozenset(words)


@dataclass(frozen=True)
class Token:
    text: str   # as written
    lower: str  # lowercase, typographic apostrophe normalised


@dataclass(frozen=True)
class FunctionMatch:
    function: RobotFunction
    keyword: str  # the phrase (or physical term) that selected it


def tokenize(text: str) -> list[Token]:
    """Words of `text` in order, as Tokens."""
    return [Token(m.group(0), m.group(0).lower().replace("’", "'")) for m in _WORD.finditer(text)]


def _text_of(entry: object, where: str) -> str:
    """A word or phrase entry of the configuration, refused unless it is a string.

    YAML 1.1 reads the unquoted words no, yes, on, off, true, false, y, n as booleans: a negation
    `no` would become False and then the phrase "false", silently.
    """
    if not isinstance(entry, str):
        raise KeywordConfigError(f"{where}: entry {entry!r} is a {type(entry).__name__}, not a "
                                 f"word or phrase (YAML reads unquoted no/yes/on/off as booleans:"
                                 f" quote it)")
    return entry


def phrase_of(entry: object, where: str) -> Phrase:
    """A configuration phrase as a tuple of lowercase words; raises KeywordConfigError."""
    words = tuple(w.lower().replace("’", "'") for w in _WORD.findall(_text_of(entry, where)))
    if not words:
        raise KeywordConfigError(f"{where}: {entry!r} contains no word")
    return words


@functools.lru_cache(maxsize=4096)
def inflections(word: str) -> frozenset[str]:
    """A keyword word and its regular inflections (remind: reminds, reminded, reminding), so that
    "reminded me", as a recogniser may hear "remind me", still matches."""
    forms = {word, word + "s", word + "es", word + "ed", word + "ing"}
    if word.endswith("e"):
        forms |= {word + "d", word[:-1] + "ing"}
    return frozenset(forms)


def _matches_at(words: Sequence[str], start: int, phrase: Phrase) -> bool:
    return all(words[start + k] in inflections(part) for k, part in enumerate(phrase))


def find_phrases(words: Sequence[str], phrases: Iterable[Phrase]) -> list[tuple[int, Phrase]]:
    """All (start index, phrase) where a phrase (or a regular inflection of its words) occurs
    in the word list, sorted by start, longer phrases first."""
    found: list[tuple[int, Phrase]] = []
    for phrase in phrases:
        found.extend((i, phrase) for i in range(len(words) - len(phrase) + 1)
                     if _matches_at(words, i, phrase))
    return sorted(found, key=lambda hit: (hit[0], -len(hit[1])))


def check_text(text: str, config: KeywordConfig,
               is_known_name: Callable[[str], bool]) -> list[Token]:
    """Refuse empty, over-long and non-English text; return its tokens otherwise.

    Args:
        is_known_name: callable(word) -> bool, true for a household member's name.
    Raises:
        RejectedUtterance naming the problem.
    """
    if not text or not text.strip():
        raise RejectedUtterance("empty text")
    if len(text) > config.max_text_chars:
        raise RejectedUtterance(f"text of {len(text)} characters exceeds the limit of "
                                f"{config.max_text_chars}")
    tokens = tokenize(text)
    if not tokens:
        raise RejectedUtterance(f"no words in text {text!r}")
    vocabulary = config.vocabulary()
    english = sum(1 for t in tokens if t.lower in vocabulary or is_known_name(t.text))
    share = english / len(tokens)
    if share < config.min_english_share:
        raise RejectedUtterance(f"text does not look English ({english} of {len(tokens)} words "
                                f"known, need {config.min_english_share:.0%}): {text!r}")
    return tokens


def _covered(start: int, size: int, spans: Iterable[tuple[int, int]]) -> bool:
    return any(s <= start and start + size <= s + n for s, n in spans)


def _negated(words: Sequence[str], start: int, config: KeywordConfig) -> bool:
    window = words[max(0, start - config.negation_window):start]
    return any(True for _ in find_phrases(window, config.negations))


def find_physical_terms(words: Sequence[str], config: KeywordConfig) -> tuple[str, ...]:
    """§3.3: the physical terms of the dictionary that occur in the sentence, in order.

    Beyond the seed's plain dictionary look-up, a term inside an exception phrase ("fell asleep")
    or shortly after a negation ("I don't have a headache") does not count.
    """
    exceptions = [(s, len(p)) for s, p in find_phrases(words, config.physical_exceptions)]
    return tuple(" ".join(phrase) for start, phrase in find_phrases(words, config.physical_terms)
                 if not _covered(start, len(phrase), exceptions)
                 and not _negated(words, start, config))


def extract_function(words: Sequence[str], config: KeywordConfig,
                     physical_terms: Sequence[str]) -> FunctionMatch | None:
    """Fig. 3-15: the robot function requested by the earliest keyword; with no keyword, the
    physical function when a physical term occurs; None when nothing is requested."""
    hits: list[tuple[int, int, str, Phrase]] = []
    for function in config.functions.values():
        hits.extend((start, -len(phrase), function.name, phrase)
                    for start, phrase in find_phrases(words, function.keywords))
    if hits:
        _, _, name, phrase = min(hits)
        return FunctionMatch(config.functions[name], " ".join(phrase))
    if physical_terms:
        return FunctionMatch(config.functions[config.physical_function], physical_terms[0])
    return None


def find_target(tokens: Sequence[Token], config: KeywordConfig,
                canonical_name: Callable[[str], str | None]) -> str | None:
    """The household member the sentence names, or None (the speaker is the target).

    Args:
        canonical_name: callable(word) -> the person's stored name, or None if nobody is called so.
    Raises:
        RejectedUtterance when a capitalised unknown word stands where a name is expected
        ("check Zed status").
    """
    vocabulary = config.vocabulary()
    for token in tokens:
        if token.lower not in vocabulary:
            name = canonical_name(token.text)
            if name:
                return name
    words = [t.lower for t in tokens]
    for start, phrase in find_phrases(words, config.person_slot_after):
        after = start + len(phrase)
        if after < len(tokens):
            word = tokens[after]
            if word.text[:1].isupper() and word.lower not in vocabulary:
                raise RejectedUtterance(f"unknown target name {word.text!r}: nobody of that name "
                                        f"in the human database")
    return None


def _function_from_yaml(name: str, entry: Any) -> RobotFunction:
    where = f"functions.{name}"
    try:
        function = RobotFunction(
            name=name, code=int(entry["code"]), duration_s=int(entry["duration_s"]),
            served_to=entry.get("served_to", TARGET),
            keywords=tuple(phrase_of(k, where) for k in entry["keywords"]))
    except (KeyError, TypeError) as error:
        raise KeywordConfigError(f"{where}: missing or malformed field {error}") from error
    if function.served_to not in (TARGET, CAREGIVER):
        raise KeywordConfigError(f"{where}.served_to must be {TARGET!r} or {CAREGIVER!r}; "
                                 f"got {function.served_to!r}")
    if function.duration_s < 0 or not function.keywords:
        raise KeywordConfigError(f"{where}: duration_s must be >= 0 and keywords non-empty")
    return function


def _validate(config: KeywordConfig) -> None:
    codes = [f.code for f in config.functions.values()]
    if len(set(codes)) != len(codes):
        raise KeywordConfigError(f"functions: codes must be unique; got {codes}")
    if config.physical_function not in config.functions:
        raise KeywordConfigError(f"physical_function {config.physical_function!r} is not a "
                                 f"function")
    for head, follow_ups in config.chains.items():
        for name in (head, *follow_ups):
            if name not in config.functions:
                raise KeywordConfigError(f"chains.{head}: {name!r} is not a function")
    missing = set(PRIORITY_LEVELS) - set(config.status_codes)
    if missing:
        raise KeywordConfigError(f"status_codes lacks {sorted(missing)}")
    if not 0.0 <= config.min_english_share <= 1.0 or config.max_text_chars <= 0:
        raise KeywordConfigError("min_english_share must lie in [0, 1] and max_text_chars > 0")
    if config.negation_window < 0:
        raise KeywordConfigError(f"negation_window must be >= 0; got {config.negation_window}")


def keyword_config_from_dict(data: Any) -> KeywordConfig:
    """KeywordConfig from the parsed YAML mapping; raises KeywordConfigError."""
    try:
        config = KeywordConfig(
            functions={name: _function_from_yaml(name, entry)
                       for name, entry in data["functions"].items()},
            physical_function=data["physical_function"],
            physical_terms=tuple(phrase_of(t, "physical_terms") for t in data["physical_terms"]),
            physical_exceptions=tuple(phrase_of(t, "physical_exceptions")
                                      for t in data.get("physical_exceptions") or ()),
            negations=tuple(phrase_of(t, "negations") for t in data.get("negations") or ()),
            negation_window=int(data.get("negation_window", 0)),
            sentiment_neutral_words=frozenset(
                _text_of(w, "sentiment_neutral_words").lower()
                for w in data.get("sentiment_neutral_words") or ()),
            chains={name: tuple(follow) for name, follow in (data.get("chains") or {}).items()},
            status_codes={k: int(v) for k, v in data["status_codes"].items()},
            caregiver=str(data["caregiver"]),
            default_place=str(data["default_place"]),
            person_slot_after=tuple(phrase_of(p, "person_slot_after")
                                    for p in data["person_slot_after"]),
            max_text_chars=int(data["max_text_chars"]),
            min_english_share=float(data["min_english_share"]),
            english_words=frozenset(_text_of(w, "english_words").lower()
                                    for w in data["english_words"]))
    except (KeyError, TypeError, AttributeError) as error:
        raise KeywordConfigError(f"keyword configuration: missing or malformed {error}") from error
    _validate(config)
    return config


def load_keyword_config(path: str | Path) -> KeywordConfig:
    """KeywordConfig from config/keywords.yaml; raises KeywordConfigError naming the file."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise KeywordConfigError(f"cannot read keyword configuration {path}: {error}") from error
    try:
        return keyword_config_from_dict(data)
    except KeywordConfigError as error:
        raise KeywordConfigError(f"{path}: {error}") from error
