"""Reading a person's spoken answers to the robot's introduction questions (thesis 000 §3.2.3:
the robot asks an unknown person their name, gender and age).

The answers arrive as speech-to-text output, so the readers accept what Whisper writes ("I am
seventy two years old" comes back as "I am 72 years old") and refuse, with a reason the robot
can say, anything they cannot read with confidence ("I'm at Woven." for "I'm a woman.").
"""
import re
from collections.abc import Iterable, Sequence

MAX_AGE = 150          # [years] human_db.model.MAX_AGE: an older age is a misheard number
MAX_NAME_WORDS = 3     # "Frank", "Frank Miller", "Mary Ann Smith"

# Phrases that introduce a name; the name is the words after them up to the end of the clause.
_NAME_LEADS = re.compile(r"\b(?:my name is|my name's|name is|call me|i am|i'm|it is|it's|this is)"
                         r"\s+", re.IGNORECASE)
_CLAUSE_END = re.compile(r"[.,;:!?]")
_WORD = re.compile(r"[A-Za-z][A-Za-z'-]*")
# Words that are no part of a name: what people say around one, or instead of one ("I don't know",
# "I'm visiting", "I mean"), and what speech-to-text makes of a mumble ("I'm at Berson").
NOT_NAME_WORDS = frozenset("""
    a an the and or but not no yes yeah okay ok sorry sure well so just also too very really
    i me my mine you your we our he him his she her they them it its is am are was be been
    do does did don't doesn't i'm it's that's know think mean guess here there
    from at in on of to for with by
    hello hi hey good morning afternoon evening nice meet pleased glad thanks thank please
    visiting visitor guest friend new name called man woman male female lady gentleman boy girl
    years year old age what who why how
    """.split())

MALE_WORDS = frozenset({"man", "male", "gentleman", "boy", "guy", "he", "him", "mister", "mr"})
FEMALE_WORDS = frozenset({"woman", "female", "lady", "girl", "she", "her", "miss", "mrs", "ms"})
NEGATIONS = frozenset({"not", "never", "neither", "nor", "isn't", "aren't", "ain't"})

_UNITS = {w: i for i, w in enumerate(
    "zero one two three four five six seven eight nine ten eleven twelve thirteen fourteen "
    "fifteen sixteen seventeen eighteen nineteen".split())}
_TENS = {w: 10 * (i + 2) for i, w in enumerate(
    "twenty thirty forty fifty sixty seventy eighty ninety".split())}
_DIGITS = re.compile(r"\d[\d,]*")


class AnswerError(ValueError):
    """An answer that cannot be read; the message says what was not understood."""


def _words(text: str) -> list[str]:
    return [w.lower() for w in _WORD.findall(text)]


def _name_from_words(words: Iterable[str], text: str) -> str:
    """Leading name-like words (up to MAX_NAME_WORDS), capitalised; AnswerError when none."""
    name: list[str] = []
    for word in words:
        if word.lower() in NOT_NAME_WORDS:
            break
        name.append(word[:1].upper() + word[1:])
    if not name or len(name) > MAX_NAME_WORDS:
        raise AnswerError(f"I did not catch a name in '{text}'")
    return " ".join(name)


def parse_name(text: str) -> str:
    """The name in an answer to "What is your name?": "My name is Frank", "I'm Frank", "Frank".

    Returns the name with each word capitalised; raises AnswerError naming the answer."""
    text = text.strip()
    for lead in _NAME_LEADS.finditer(text):   # "Hi, it's me, my name is Frank": the second lead
        clause = _CLAUSE_END.split(text[lead.end():], maxsplit=1)[0]
        try:
            return _name_from_words(_WORD.findall(clause), text)
        except AnswerError:
            continue
    if _NAME_LEADS.search(text):
        raise AnswerError(f"I did not catch a name in '{text}'")
    words = _WORD.findall(text)
    if not words or len(words) > MAX_NAME_WORDS or _DIGITS.search(text):
        raise AnswerError(f"I did not catch a name in '{text}'")
    if any(w.lower() in NOT_NAME_WORDS for w in words):
        raise AnswerError(f"I did not catch a name in '{text}'")
    return _name_from_words(words, text)


def parse_gender(text: str) -> str:
    """"female" or "male" from "I am a man / male / woman / female"; AnswerError otherwise."""
    words = set(_words(text))
    male, female = words & MALE_WORDS, words & FEMALE_WORDS
    if words & NEGATIONS:
        raise AnswerError(f"I am not sure whether '{text}' means a man or a woman")
    if bool(male) == bool(female):
        raise AnswerError(f"I did not catch whether you are a man or a woman in '{text}'")
    return "male" if male else "female"


def _number_words(words: Sequence[str]) -> int | None:
    """The first run of English number words ("seventy two", "a hundred and one") as an int,
    None when the words hold none."""
    value, found = 0, False
    for k, word in enumerate(words):
        if word in _UNITS or word in _TENS:
            value += _UNITS.get(word, 0) + _TENS.get(word, 0)
            found = True
        elif word == "hundred" and (found or (k > 0 and words[k - 1] in ("a", "one"))):
            value = max(value, 1) * 100
            found = True
        elif found and word != "and":
            break
    return value if found else None


def parse_age(text: str) -> int:
    """Age [years] from "I am 72 years old", "72", "seventy-two"; AnswerError when there is no
    number or it is no plausible age (> MAX_AGE: "twenty nine" heard as "20,000,000")."""
    digits = _DIGITS.search(text)
    if digits:
        age = int(digits.group(0).replace(",", ""))
    else:
        spoken = _number_words(_words(text.replace("-", " ")))
        if spoken is None:
            raise AnswerError(f"I did not catch an age in '{text}'")
        age = spoken
    if not 0 < age <= MAX_AGE:
        raise AnswerError(f"{age} years is not an age I can believe")
    return age


YES_WORDS = frozenset({"yes", "yeah", "yep", "yup", "correct", "right", "sure", "exactly"})
NO_WORDS = frozenset({"no", "nope", "wrong", "not", "incorrect"})


def parse_yes_no(text: str) -> bool:
    """True for "Yes.", "Yeah, that's right", False for "No.", "Nope"; AnswerError when the
    answer holds both or neither."""
    words = set(_words(text))
    yes, no = bool(words & YES_WORDS), bool(words & NO_WORDS)
    if yes == no:
        raise AnswerError(f"I did not catch a yes or a no in '{text}'")
    return yes


def closest_name(name: str, names: Iterable[str], similarity: float) -> str:
    """The name of `names` spelt most like `name` with a similarity (difflib ratio, case
    ignored) of at least `similarity`, or "" when none is (a misheard "Carl" for "Carol")."""
    import difflib
    best, best_ratio = "", similarity
    for candidate in names:
        ratio = difflib.SequenceMatcher(None, name.lower(), candidate.lower()).ratio()
        if ratio >= best_ratio:
            best, best_ratio = candidate, ratio
    return best
