"""The basic instruction classes of the direction follower (thesis 002, Table 3.1-1): the one
list every other module reads (phrase sets, route oracle, expert, demonstrations, training,
evaluation, the instruction layer's corner limit, the scripts' `--classes` choices).

A class's number is its label everywhere: in penguin_base's record format (`R;<class>`), in
the phrase sets and as Z_w's output c - 1 of the network (so numbers run 1 … len(CLASSES) with
no gap, and a model trained on this list knows exactly these classes).

Per class:
- `motion`: STRAIGHT (to the corridor's end), BACK (turn around where it stands) or TURN;
- `side`: "left" / "right" for a turn, None otherwise;
- `at`: where a turn turns: None = the first corner with a branch on its side; "second" /
  "third" = that corner, counting the corners over both sides (`corner` gives the number);
  "end" = the corner at the corridor's end. It is the tag of the kind-B phrases
  (`suffix_turn_change`) of config/semnav_phrases.yaml;
- `phrase_set`: the phrase set of its core phrase in config/semnav_phrases.yaml ("class1",
  "class4", or "class_turn" with the side as `{dir}`);
- `mirror`: the class of its left-right mirror image (right and left swapped).
"""
from collections.abc import Sequence
from dataclasses import dataclass

STRAIGHT, BACK, TURN = "straight", "back", "turn"
SIDES = ("right", "left")
CORNER_NUMBERS = {"second": 2, "third": 3}   # `at` of a counted corner -> its number


@dataclass(frozen=True)
class InstructionClass:
    """One row of Table 3.1-1 and the facts the pipeline needs about it."""

    number: int                  # the label (1 … len(CLASSES))
    name: str                    # its representative basic instruction
    motion: str                  # STRAIGHT, BACK or TURN
    phrase_set: str              # phrase set of its core phrase
    mirror: int                  # class of its left-right mirror image
    side: str | None = None      # "left" / "right" for a turn
    at: str | None = None        # None (first branch on its side), "second", "third", "end"

    @property
    def corner(self) -> int | None:
        """The corner it turns at, counted over both sides (2, 3), or None."""
        return CORNER_NUMBERS.get(self.at) if self.at is not None else None


def check_classes(classes: Sequence[InstructionClass]) -> None:
    """Raise ValueError where a class list contradicts itself (CLASSES is checked at import)."""
    numbers = [c.number for c in classes]
    if numbers != list(range(1, len(classes) + 1)):
        raise ValueError(f"instruction classes must be numbered 1..{len(classes)} in order, "
                         f"got {numbers}")
    by_id = {c.number: c for c in classes}
    for c in classes:
        if c.motion not in (STRAIGHT, BACK, TURN):
            raise ValueError(f"class {c.number}: unknown motion {c.motion!r}")
        if (c.side in SIDES) != (c.motion == TURN) or (c.at is not None and c.motion != TURN):
            raise ValueError(f"class {c.number}: a side (right / left) and `at` for turns only")
        if c.at not in (None, "end", *CORNER_NUMBERS):
            raise ValueError(f"class {c.number}: unknown `at` {c.at!r}")
        m = by_id.get(c.mirror)
        if (m is None or m.mirror != c.number or (m.motion, m.at) != (c.motion, c.at)
                or (c.side is not None and m.side == c.side)):
            raise ValueError(f"class {c.number}: mirror {c.mirror} is not its mirror image")
    turns = [(c.side, c.at) for c in classes if c.motion == TURN]
    if len(set(turns)) != len(turns):
        raise ValueError("two turn classes with the same side and `at`")


# Table 3.1-1.
CLASSES = (
    InstructionClass(1, "go straight to the end", STRAIGHT, "class1", mirror=1),
    InstructionClass(2, "turn right", TURN, "class_turn", mirror=3, side="right"),
    InstructionClass(3, "turn left", TURN, "class_turn", mirror=2, side="left"),
    InstructionClass(4, "go back (turn around)", BACK, "class4", mirror=4),
    InstructionClass(5, "turn right at the second corner", TURN, "class_turn", mirror=6,
                     side="right", at="second"),
    InstructionClass(6, "turn left at the second corner", TURN, "class_turn", mirror=5,
                     side="left", at="second"),
    InstructionClass(7, "turn right at the third corner", TURN, "class_turn", mirror=8,
                     side="right", at="third"),
    InstructionClass(8, "turn left at the third corner", TURN, "class_turn", mirror=7,
                     side="left", at="third"),
    InstructionClass(9, "go straight to the end and turn right", TURN, "class_turn", mirror=10,
                     side="right", at="end"),
    InstructionClass(10, "go straight to the end and turn left", TURN, "class_turn", mirror=9,
                     side="left", at="end"),
)
check_classes(CLASSES)

CLASS_IDS = tuple(c.number for c in CLASSES)
NUM_CLASSES = len(CLASSES)
BY_ID = {c.number: c for c in CLASSES}
NAMES = {c.number: c.name for c in CLASSES}


def ids(**facts: object) -> tuple[int, ...]:
    """Numbers of the classes whose fields equal `facts`, in list order, e.g.
    ids(motion=TURN, at=None) -> (2, 3)."""
    return tuple(c.number for c in CLASSES
                 if all(getattr(c, key) == value for key, value in facts.items()))


def get(number: int) -> InstructionClass:
    """The class numbered `number`; ValueError naming the known numbers otherwise."""
    try:
        return BY_ID[number]
    except (KeyError, TypeError):
        raise ValueError(f"unknown instruction class {number!r} "
                         f"({CLASS_IDS[0]}..{CLASS_IDS[-1]})") from None


# Counting modes of the counted classes (5-8), beyond the seed: "turn right at the second
# corner" counts the corners over both sides (Table 3.1-1), "take the second right" counts the
# branches on the turning side only. The instruction layer tells them apart
# (instruction_layer.counting_mode); the class stays the same.
COUNT_CORNERS, COUNT_SIDE = "corners", "side"
COUNTINGS = (COUNT_CORNERS, COUNT_SIDE)


# Derived tables.
SIDE = {c.number: c.side for c in CLASSES if c.side}                  # turn class -> side
TURN_CLASSES = {(c.side, c.at): c.number for c in CLASSES if c.motion == TURN}  # -> turn class
COUNTING_IDS = tuple(c.number for c in CLASSES if c.corner)          # counted corners (5-8)
MAX_CORNER = max(c.corner for c in CLASSES if c.corner)              # the last corner counted
MIRRORED_CLASS = {c.number: c.mirror for c in CLASSES}               # right and left swapped
# a turn before the corridor's end -> the turn at the corridor's end on the same side
END_TURN = {c.number: TURN_CLASSES[(c.side, "end")] for c in CLASSES
            if c.motion == TURN and c.at != "end"}
TURN_AT = tuple(dict.fromkeys(c.at for c in CLASSES if c.at))        # kind-B tags, list order
