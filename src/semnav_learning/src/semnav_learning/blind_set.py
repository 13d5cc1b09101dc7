"""Blind sets of directions (config/semnav_blind_directions.yaml): sentences written in words of
their own, with the class sequence they mean, scored against the instruction layer.

A blind set is a test only: nothing is trained on it and no model, phrase or threshold is chosen
by it. An entry is right when the classes read from it equal its `classes` or its `or` reading;
a turn read to the other side than meant (at the same position) is a wrong-side reading, the
error that sends a robot the wrong way; so is a turn around read where a class 1-3 direction
(straight on, the first right or left) was meant and no turn around (`turned_back`).
"""
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from semantic_nav.instruction_classes import BACK, BY_ID, CLASS_IDS, STRAIGHT, TURN, ids

BACK_ID = ids(motion=BACK)[0]                                    # class 4, turn around
FIRST_MOVES = ids(motion=STRAIGHT) + ids(motion=TURN, at=None)   # classes 1, 2, 3

COUNT_MODES = ("corner", "side")


class BlindSetError(ValueError):
    """A blind-set file that cannot be used; the message names the file and the entry."""


@dataclass(frozen=True)
class BlindEntry:
    text: str
    classes: tuple                  # class numbers of its simple instructions, in order
    readings: tuple                 # (classes, and the equivalent `or` reading if any)
    count: tuple                    # per instruction: "corner" or "side"


def _classes(value, where):
    if (not isinstance(value, list) or not value
            or not all(isinstance(c, int) and c in CLASS_IDS for c in value)):
        raise BlindSetError(f"{where}: expected a list of class numbers "
                            f"{CLASS_IDS[0]}..{CLASS_IDS[-1]}, got {value!r}")
    return tuple(value)


def load_blind_set(path):
    """[BlindEntry] of a blind-set YAML file; BlindSetError naming the file and entry."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise BlindSetError(f"{path}: {error}") from None
    if not isinstance(data, dict) or not isinstance(data.get("entries"), list):
        raise BlindSetError(f"{path}: expected a mapping with a list `entries`")
    entries, seen = [], set()
    for i, item in enumerate(data["entries"]):
        where = f"{path}: entries[{i}]"
        if not isinstance(item, dict) or not isinstance(item.get("text"), str):
            raise BlindSetError(f"{where}: expected a mapping with a `text`")
        unknown = set(item) - {"text", "classes", "or", "count"}
        if unknown:
            raise BlindSetError(f"{where}: unknown key {sorted(unknown)[0]!r}")
        if item["text"] in seen:
            raise BlindSetError(f"{where}: {item['text']!r} is listed twice")
        seen.add(item["text"])
        classes = _classes(item.get("classes"), f"{where}.classes")
        readings = (classes,) + ((_classes(item["or"], f"{where}.or"),) if "or" in item else ())
        count = tuple(item.get("count", ["corner"] * len(classes)))
        if len(count) != len(classes) or not set(count) <= set(COUNT_MODES):
            raise BlindSetError(f"{where}.count: one of {COUNT_MODES} per class, got {count!r}")
        entries.append(BlindEntry(item["text"], classes, readings, count))
    return entries


def wrong_side(expected, read):
    """True when a turn of `expected` is read, at the same position, as a turn to the other
    side."""
    for want, got in zip(expected, read):
        a, b = BY_ID[want].side, BY_ID.get(got) and BY_ID[got].side
        if a is not None and b is not None and a != b:
            return True
    return False


def turned_back(readings, read):
    """True when `read` holds a turn around though a meant reading has a class 1-3 part and
    none a turn around."""
    return (read is not None and BACK_ID in read and all(BACK_ID not in r for r in readings)
            and any(c in FIRST_MOVES for r in readings for c in r))


@dataclass
class BlindScore:
    """Per entry: (entry, classes read or None, reason it was refused or "")."""

    results: list = field(default_factory=list)

    @property
    def right(self):
        return [r for r in self.results if r[1] is not None and tuple(r[1]) in r[0].readings]

    @property
    def accuracy(self):
        return len(self.right) / len(self.results) if self.results else 0.0

    @property
    def wrong_sides(self):
        return [r for r in self.results
                if r[1] is not None and all(wrong_side(reading, r[1]) for reading in r[0].readings)]

    @property
    def turned_back(self):
        return [r for r in self.results if turned_back(r[0].readings, r[1])]

    @property
    def misses(self):
        right = {id(r) for r in self.right}
        return [r for r in self.results if id(r) not in right]

    def per_group(self):
        """{first class, or "several": (right, total)}."""
        groups = {}
        right = {id(r) for r in self.right}
        for r in self.results:
            key = r[0].classes[0] if len(r[0].classes) == 1 else "several"
            tally = groups.setdefault(key, [0, 0])
            tally[0] += id(r) in right
            tally[1] += 1
        return groups


def score_blind_set(entries, classify, refusals=(ValueError,)):
    """BlindScore of `classify(text) -> [class, ...]` on `entries`; an exception of
    `refusals` (unknown words, an unfollowable sentence) counts as a miss with its reason."""
    score = BlindScore()
    for entry in entries:
        try:
            score.results.append((entry, list(classify(entry.text)), ""))
        except refusals as error:
            score.results.append((entry, None, str(error)))
    return score


def format_blind_score(score):
    """The lines classify_instruction --blind prints."""
    n = len(score.results)
    lines = [f"blind set: {len(score.right)}/{n} = {score.accuracy:.2%} read as meant; "
             f"{len(score.wrong_sides)} to the wrong side; {len(score.turned_back)} class 1-3 "
             f"directions read as a turn around"]
    groups = score.per_group()
    lines.append("per class: " + ", ".join(f"{k}: {h}/{t}" for k, (h, t) in groups.items()))
    for entry, read, reason in score.misses:
        got = " ".join(map(str, read)) if read is not None else f"refused ({reason})"
        side = "  WRONG SIDE" if read is not None and all(
            wrong_side(r, read) for r in entry.readings) else ""
        want = " or ".join(" ".join(map(str, r)) for r in entry.readings)
        lines.append(f"  {entry.text!r}: meant {want}, read {got}{side}")
    return lines
