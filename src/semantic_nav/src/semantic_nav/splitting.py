"""Instruction layer, splitting stage (thesis 002 §3.1): a sentence -> its simple instructions.

The seed splits at punctuation only ("seed"). "spoken" splitting (beyond the seed, the default)
reads directions as people give them: it splits at connectives and after a turn, and joins
pieces that are no instruction of their own (a greeting, a place said first, a lead-in, a
"don't ...", a "take it") to the instruction they belong to.
"""
import re


class InstructionError(ValueError):
    """An instruction that cannot be turned into sentence vectors; the message says why."""


# Lower-case tokens as in GloVe 6B: words, numbers, clitics ('s, 'd) and n't split off.
TOKEN = re.compile(r"[a-z0-9]+(?=n't)|n't|'[a-z]+|[a-z0-9]+(?:-[a-z0-9]+)*")
# §3.1: "we simply use punctuation marks to split sentences into simple instruction".
PUNCTUATION = re.compile(r"[.,;:!?\n]+")
# Beyond the seed ("spoken" splitting): spoken text (speech recognition) has no punctuation, and
# people chain directions with connectives: "then", "after that" and "once you're there" also end
# an instruction. "and" alone splits only between two turns (split_turns): "go straight to the
# end and turn right" is one instruction (class 9).
THEN = re.compile(r"\b(?:and\s+)?(?:then|after\s+that|once\s+you(?:'re|\s+are)\s+there|"
                  r"once\s+there)\b")
LEADING_CONNECTIVE = re.compile(r"^(?:and\s+then|then|and)\b\s*")
TRAILING_CONNECTIVE = re.compile(r"\s*\b(?:and|and\s+then|then)$")

SPLITTINGS = ("seed", "spoken")
# A piece naming none of these asks for no motion ("hey robot", "please", "if you don't mind",
# "at the second junction"): "spoken" splitting joins it to the next piece (the last to the one
# before), so a comma after a greeting or a fronted "at the second corner, turn left" does not
# make an instruction of its own.
MOTION_WORDS = frozenset("""
left right lefts rights straight back around round forward forwards ahead down along turn turns
go goes walk drive head move continue keep follow take make hang proceed pass skip return
reverse spin flip carry roll veer bear swing u-turn backward backwards come
""".split())
# A piece that moves on without turning or arriving ("go past the first corner", "go straight")
# says how to reach the turn that follows: "go past two corners, then turn left" is one
# instruction (class 8), not "go ... to the end" then "turn left". "spoken" splitting joins such
# a lead-in to the next piece. A piece naming a turn, an end, a passing or a stretch of corridor
# ("walk down this aisle": the seed's class 1) is no lead-in.
TURN_WORDS = frozenset("""
left right lefts rights around round back backward backwards reverse return u-turn u other
one-eighty eighty
""".split())
END_WORDS = frozenset("""
end ends wall far further farther all until till possible stops finishes aisle corridor hall
hallway passage
""".split())
PASSING_WORDS = frozenset("past pass passed passing skip ignore behind".split())
SIDE_WORDS = frozenset("left right lefts rights".split())
# "and" after turning around ends the instruction when a direction follows: "turn around and take
# the third left" is class 4, then class 8 ("turn around and go back" stays one class 4). "back"
# turns around unless it is a place ("to the back and turn left").
ABOUT_TURN_AND = re.compile(
    r"^(.*\b(?:around|round|u-turn|u turn|one-eighty|one eighty|the other way|"
    r"(?<!the )(?<!your )(?<!its )back))\s+and\s+(.+)$")
ONWARD_WORDS = frozenset("left right lefts rights straight end".split())
# "and" after a turn ends it when another turn or a going on to an end follows: "take the second
# left and at the end turn right" is class 6, then class 9; "turn right and go to the end" is
# class 2, then class 1 (not 9, the end first). Not after a turn that is passed, counted or
# refused ("skip the first left and turn left at the next one", "count two corners and turn
# right at the second", "let one right go by and take the next").
TURN_AND = re.compile(r"\s+and\s+")
NOT_A_TURN_TAKEN = PASSING_WORDS | frozenset(
    "miss missing let count counting not n't never".split())
# A piece that refuses a turn ("don't take the first right", "don't turn anywhere") says which
# turn is meant only together with the piece after it: it is joined to that piece when that
# names no side of its own ("don't take the first right, take the second"); otherwise it is
# left out ("don't turn left, turn right", "go forward, don't turn anywhere"). A refusal that
# offers its alternative ("not this right but the next one") is an instruction of its own.
REFUSAL = re.compile(r"^(?:(?:and|but|so|just|please|no|oh)\s+)*"
                     r"(?:do\s+not|don't|dont|never|not)\b(?!.*\b(?:but|instead)\b)")
# A piece that only points back ("take it", "go down there", "take that one") is part of the
# instruction before it: "there's a right coming up, take it" is one class 2.
POINTING = frozenset("it that there this one them".split())
POINTING_PIECE = POINTING | frozenset("""
take go turn make use do head down into in up please just and so ok okay you can could will
""".split())
# A reply word in front of a direction: "all right, keep going straight" is class 1, and so is
# "right, go straight to the end" (a bare "right" only before a comma and a verb: "right, at
# the first corner" is a turn).
ALL_RIGHT = re.compile(r"^(?:(?:ok|okay|so|well|um|uh)[\s,]+)*(?:all\s+right|alright)\b[\s,.!;:]*")
BARE_RIGHT = re.compile(
    r"^(?:(?:ok|okay|so|well|um|uh)[\s,]+)*right\s*[,.!;:]\s*"
    r"(?=(?:(?:so|now|ok|okay|um|uh|just|please)\s+)*(?:go|keep|head|walk|drive|carry|continue|"
    r"follow|move|turn|take|make|proceed|hang|you|i|we|could|can|would)\b)")
# "right" as "all the way" after a verb of going on: "drive right to the end of the hall", "go
# right down to the end" are class 1 (not a right turn).
RIGHT_TO_THE_END = re.compile(
    r"\b((?:go|goes|drive|walk|head|run|roll|move|carry\s+on|keep\s+going|continue|follow|"
    r"proceed|travel)(?:\s+(?!right\b|left\b|to\b)[a-z']+){0,2}?)\s+right\s+"
    r"(?=(?:(?:down|up|along|on)\s+)?(?:to|till|until)\s+the\s+(?:very\s+)?"
    r"(?:end|wall|bottom|back|far)\b)")


def split_instruction(sentence: str, splitting: str = "spoken") -> list[str]:
    """§3.1: split a sentence into simple instructions at punctuation ("seed"; a leading or
    trailing "and" / "then" is dropped). "spoken" (beyond the seed, the default) reads a reply
    word and "right" as "all the way" out first (read_spoken); it also splits at "(and) then",
    "after that", "once you're there" and "and" after a turn (split_about_turn, split_turns),
    and joins pieces that point back, refuse a turn, name no motion or only lead in to the
    instruction they belong to (join_pointing, join_refusals, join_fragments, join_lead_ins)."""
    if not isinstance(sentence, str):
        raise InstructionError(f"instruction must be text, got {type(sentence).__name__}")
    if splitting not in SPLITTINGS:
        raise InstructionError(f"unknown splitting {splitting!r} (one of {', '.join(SPLITTINGS)})")
    text = sentence.lower() if splitting == "seed" else read_spoken(sentence.lower())
    parts = []
    for clause in PUNCTUATION.split(text):
        pieces = THEN.split(clause) if splitting == "spoken" else [clause]
        for piece in pieces:
            piece = " ".join(piece.split())
            piece = TRAILING_CONNECTIVE.sub("", LEADING_CONNECTIVE.sub("", piece))
            if TOKEN.search(piece):
                parts.append(piece)
    if not parts:
        raise InstructionError(f"instruction {sentence!r} has no words")
    if splitting == "seed":
        return parts
    parts = [piece for part in parts for about in split_about_turn(part)
             for piece in split_turns(about)]
    return join_lead_ins(join_fragments(join_refusals(join_pointing(parts))))


def read_spoken(text: str) -> str:
    """`text` without a leading reply word (ALL_RIGHT, BARE_RIGHT) and with "right" meaning
    "all the way" left out (RIGHT_TO_THE_END); the rest unchanged."""
    text = BARE_RIGHT.sub("", ALL_RIGHT.sub("", text.lstrip()))
    return RIGHT_TO_THE_END.sub(r"\1 ", text)


def words(part: str) -> set[str]:
    """The set of a piece's tokens."""
    return set(TOKEN.findall(part))


def split_about_turn(part: str) -> list[str]:
    """A turn around and what follows it, when that names a direction (ABOUT_TURN_AND)."""
    match = ABOUT_TURN_AND.match(part)
    if match and ONWARD_WORDS & words(match.group(2)):
        return [match.group(1), match.group(2)]
    return [part]


def split_turns(part: str) -> list[str]:
    """A piece split at the first "and" that has a turn taken before it and, after it, a turn or
    a going on to an end (TURN_AND, NOT_A_TURN_TAKEN); the rest split again."""
    for match in TURN_AND.finditer(part):
        before, after = part[:match.start()], part[match.end():]
        taken, then = words(before), words(after)
        onward = then & SIDE_WORDS or (then & MOTION_WORDS and then & END_WORDS)
        if taken & SIDE_WORDS and not taken & NOT_A_TURN_TAKEN and onward:
            return [before] + split_turns(after)
    return [part]


def is_refusal(part: str) -> bool:
    """A piece that refuses a turn without offering its alternative (REFUSAL)."""
    return bool(REFUSAL.match(part))


def join_refusals(parts: list[str]) -> list[str]:
    """Refusals (REFUSAL) joined to the next piece when they name a side and it names none,
    else left out; a sentence of refusals only is kept as it is."""
    if all(is_refusal(part) for part in parts):
        return parts
    result: list[str] = []
    pending: str | None = None
    for part in parts:
        if is_refusal(part):
            pending = part
            continue
        if pending is not None and words(pending) & SIDE_WORDS and not words(part) & SIDE_WORDS:
            part = f"{pending} {part}"
        pending = None
        result.append(part)
    return result


def is_pointing(part: str) -> bool:
    """A piece that only points back (POINTING_PIECE words, one of them POINTING)."""
    said = words(part)
    return bool(said & POINTING) and said <= POINTING_PIECE


def join_pointing(parts: list[str]) -> list[str]:
    """Pieces that only point back (is_pointing) joined to the piece before them."""
    joined: list[str] = []
    for part in parts:
        if joined and is_pointing(part):
            joined[-1] = f"{joined[-1]} {part}"
        else:
            joined.append(part)
    return joined


def is_lead_in(part: str) -> bool:
    """A piece that only moves on: it names motion and passes corners or goes straight, and names
    no turn and no end (TURN_WORDS, END_WORDS; a passing may name the corridor)."""
    said = words(part)
    if not said & MOTION_WORDS or said & TURN_WORDS:
        return False
    return bool(said & PASSING_WORDS) or not said & END_WORDS


def join_lead_ins(parts: list[str]) -> list[str]:
    """Lead-ins (is_lead_in) joined to the piece after them; a last lead-in stays as it is."""
    joined: list[str] = []
    pending: list[str] = []
    for k, part in enumerate(parts):
        pending.append(part)
        if k == len(parts) - 1 or not is_lead_in(part):
            joined.append(" ".join(pending))
            pending = []
    return joined


def join_fragments(parts: list[str]) -> list[str]:
    """Pieces that name no motion joined to the next piece (the last to the one before); a
    sentence with no motion at all stays one piece."""
    joined: list[str] = []
    pending: list[str] = []
    for part in parts:
        pending.append(part)
        if MOTION_WORDS & words(part):
            joined.append(" ".join(pending))
            pending = []
    if pending:
        if joined:
            joined[-1] = " ".join([joined[-1], *pending])
        else:
            joined.append(" ".join(pending))
    return joined
