"""The household as a YAML file (config/household.yaml): import into and export from the store.

Layout: an optional `places` list (then every location and schedule place must be one of them)
and a `humans` list; each human has name, ip, gender, age, optional shirt_color {joint1, joint2,
joint5: [R, G, B]} (without it the robot has not met them yet and registers their shirt when it
does, thesis 000 §3.2.3), location, activity, last_seen [s] and schedules [{start, end, place,
activity}] with times as quoted "HH:MM" or "HH:MM:SS" strings (unquoted 12:30 is a base-60 number
in YAML 1.1, hence the quotes).
"""
import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import yaml

from supervision import config_file

from human_db.colour import shirt_colours
from human_db.errors import InvalidHuman
from human_db.model import DAY, Human, ScheduleEntry
from human_db.store import HumanStore

HUMAN_KEYS = ("name", "ip", "gender", "age", "shirt_color", "location", "activity", "last_seen",
              "schedules")
REQUIRED_KEYS = ("name", "gender", "age")
JOINT_KEYS = ("joint1", "joint2", "joint5")
SCHEDULE_KEYS = ("start", "end", "place", "activity")
_CLOCK = re.compile(r"^(\d{1,2}):(\d{2})(?::(\d{2}))?$")


def parse_clock(text: object, where: str) -> float:
    """'HH:MM' or 'HH:MM:SS' (24:00 allowed) -> seconds since midnight; raise InvalidHuman."""
    match = _CLOCK.match(text) if isinstance(text, str) else None
    if match is None:
        raise InvalidHuman(f"{where}: time must be a quoted 'HH:MM' or 'HH:MM:SS' string, "
                           f"got {text!r}")
    hours, minutes, seconds = (int(g or 0) for g in match.groups())
    total = hours * 3600 + minutes * 60 + seconds
    if minutes > 59 or seconds > 59 or total > DAY:
        raise InvalidHuman(f"{where}: {text!r} is not a time of day")
    return float(total)


def format_clock(seconds: float) -> str:
    """Seconds since midnight -> 'HH:MM' (or 'HH:MM:SS' when seconds are not whole minutes)."""
    whole = round(seconds)
    hours, rest = divmod(whole, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours:02d}:{minutes:02d}" + (f":{secs:02d}" if secs else "")


def load_household(path: str | Path) -> tuple[list[str], list[Human]]:
    """Read and validate a household file; return (places, [Human]). Errors name file and entry."""
    document = config_file.read_yaml(path, InvalidHuman, "household file")
    if not isinstance(document, dict) or not isinstance(document.get("humans"), list):
        raise InvalidHuman(f"{path}: expected a mapping with a 'humans' list")
    config_file.check_keys(document, ("places", "humans"), str(path), InvalidHuman)
    places = document.get("places") or []
    if not isinstance(places, list) or not all(isinstance(p, str) for p in places):
        raise InvalidHuman(f"{path}: 'places' must be a list of place names")
    humans = [human_from_dict(entry, f"{path}: humans[{i}]", places)
              for i, entry in enumerate(document["humans"])]
    return places, humans


def human_from_dict(entry: object, where: str, places: Sequence[str] = ()) -> Human:
    """One `humans` entry of a household file -> Human; raise InvalidHuman naming `where`."""
    if not isinstance(entry, dict):
        raise InvalidHuman(f"{where}: expected a mapping, got {entry!r}")
    where = f"{where} ({entry.get('name', '?')})"
    _check_keys(entry, HUMAN_KEYS, REQUIRED_KEYS, where)
    colour = entry.get("shirt_color")
    if colour is not None:
        if not isinstance(colour, dict):
            raise InvalidHuman(f"{where}: shirt_color must map {JOINT_KEYS} to [R, G, B]")
        _check_keys(colour, JOINT_KEYS, JOINT_KEYS, f"{where}: shirt_color")
    schedules = entry.get("schedules") or []
    if not isinstance(schedules, list):
        raise InvalidHuman(f"{where}: schedules must be a list")
    entries = tuple(_schedule_from_dict(s, f"{where}: schedules[{i}]")
                    for i, s in enumerate(schedules))
    try:
        human = Human(
            name=entry["name"], ip=str(entry.get("ip") or ""), gender=entry["gender"],
            age=entry["age"],
            shirt_colour=None if colour is None else tuple(colour[k] for k in JOINT_KEYS),
            location=entry.get("location") or "", activity=entry.get("activity") or "",
            last_seen=entry.get("last_seen"), schedules=entries)
    except InvalidHuman as error:  # same error class, with the file and entry in front
        raise type(error)(f"{where}: {error}") from None
    _check_places(human, places, where)
    return human


def _schedule_from_dict(entry: object, where: str) -> ScheduleEntry:
    if not isinstance(entry, dict):
        raise InvalidHuman(f"{where}: expected a mapping, got {entry!r}")
    _check_keys(entry, SCHEDULE_KEYS, ("start", "end"), where)
    end = parse_clock(entry["end"], f"{where}: end")
    start = parse_clock(entry["start"], f"{where}: start") % DAY
    try:
        return ScheduleEntry(start=start, end=end, place=entry.get("place") or "",
                             activity=entry.get("activity") or "")
    except InvalidHuman as error:
        raise InvalidHuman(f"{where}: {error}") from None


def _check_keys(entry: Mapping[str, Any], allowed: Sequence[str], required: Sequence[str],
                where: str) -> None:
    config_file.check_keys(entry, allowed, where, InvalidHuman)
    missing = [key for key in required if key not in entry]
    if missing:
        raise InvalidHuman(f"{where}: missing keys {missing}")


def _check_places(human: Human, places: Sequence[str], where: str) -> None:
    if not places:
        return
    named = [human.location] + [entry.place for entry in human.schedules]
    unknown = sorted({place for place in named if place and place not in places})
    if unknown:
        raise InvalidHuman(f"{where}: places {unknown} are not in the household's places "
                           f"{list(places)}")


def human_to_dict(human: Human) -> dict[str, Any]:
    """Human -> one `humans` entry of a household file (inverse of human_from_dict)."""
    entry: dict[str, Any] = {"name": human.name, "ip": human.ip, "gender": human.gender,
                             "age": human.age}
    if human.shirt_colour is not None:
        entry["shirt_color"] = {k: list(c) for k, c in zip(JOINT_KEYS, human.shirt_colour)}
    entry.update({"location": human.location, "activity": human.activity,
             "schedules": [{"start": format_clock(e.start), "end": format_clock(e.end),
                            "place": e.place, "activity": e.activity} for e in human.schedules]})
    if human.last_seen is not None:
        entry["last_seen"] = human.last_seen
    return entry


def dump_household(humans: Iterable[Human], places: Sequence[str] = ()) -> str:
    """A household file's text for `humans` (and `places` when given)."""
    document: dict[str, Any] = {"places": list(places)} if places else {}
    document["humans"] = [human_to_dict(human) for human in humans]
    return yaml.safe_dump(document, sort_keys=False, default_flow_style=None, allow_unicode=True)


def load_shirts(path: str | Path) -> dict[str, tuple[tuple[int, ...], ...]]:
    """A shirts file ({shirts: {name: {joint1, joint2, joint5: [R, G, B]}}}: the shirts people
    were registered in before the run) -> {name: ((r, g, b) x 3)}; InvalidHuman names the file
    and the entry."""
    document = config_file.read_yaml(path, InvalidHuman, "shirts file")
    if not isinstance(document, dict) or set(document) != {"shirts"} or \
            not isinstance(document["shirts"], dict):
        raise InvalidHuman(f"{path}: expected a mapping with only a 'shirts' mapping")
    shirts: dict[str, tuple[tuple[int, ...], ...]] = {}
    for name, colour in document["shirts"].items():
        where = f"{path}: shirts: {name}"
        if not isinstance(colour, dict):
            raise InvalidHuman(f"{where}: must map {JOINT_KEYS} to [R, G, B]")
        _check_keys(colour, JOINT_KEYS, JOINT_KEYS, where)
        shirts[str(name)] = tuple(tuple(int(c) for c in joint) for joint in shirt_colours(
            [colour[k] for k in JOINT_KEYS], where))
    return shirts


def register_shirts(store: HumanStore, path: str | Path, now: float | None = None) -> list[str]:
    """Give each person of a shirts file that shirt (source "register"): a run that starts with
    everyone already met. Returns the names; UnknownHuman names a person the store lacks."""
    shirts = load_shirts(path)
    for name, shirt in shirts.items():
        store.update(name, now=now, source="register", shirt_colour=shirt)
    return list(shirts)


def import_household(store: HumanStore, path: str | Path, replace: bool = False,
                     now: float | None = None) -> list[str]:
    """Register every person of a household file in one transaction; return their names."""
    _, humans = load_household(path)
    store.register_all(humans, replace=replace, now=now)
    return [human.name for human in humans]


def export_household(store: HumanStore, path: str | Path, places: Sequence[str] = ()) -> None:
    """Write the store's household to `path` (YAML)."""
    text = dump_household(store.humans(), places)
    with open(path, "w", encoding="utf-8") as stream:
        stream.write(text)
