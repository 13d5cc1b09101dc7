"""A scripted household scenario (ROS-free): timed phone requests and the people's moves.

A scenario file (config/scenarios/*.yaml) names the sim2d world whose people move at their own
times, unannounced to the robot (config/household.yaml holds their daily schedules, which the
robot knows; `day_start` sets the time of day at simulated time 0), the household (phone IPs),
and the requests: at `time` seconds of simulated
time, `person` says `text` into their phone; `spoken: true` sends it as synthesised audio through
the speech-to-text node instead of as text. `visitors` are people of the world who are not in
the household: the robot meets them (thesis 000 §3.2.3, perception's introduction node) and they
answer its questions through the speech path; their requests are sent only once they are
registered. A resident whose move in the world puts on a new shirt (a schedule entry's
`shirt_colour`) is a stranger to the robot's camera until it asks their name again; they answer
"My name is NAME." on the robot's microphone. The run ends when every request is served; with
`finish_own: true` also once the robot's own instructions open at that moment are closed (new
ones it gives itself after are not waited for), within `timeout_s`. `ros_scenario.py` plays
it; `scenario_report.py` writes what happened.
"""
import math
import re
from dataclasses import dataclass
from pathlib import Path

from human_db.errors import InvalidHuman
from human_db.household import load_household
from matplotlib.path import Path as Polygon
from supervision import config_file
from tamp_resources import resource
from task_planner.planner_registry import PLANNERS


# What a visitor answers: the question is recognised by a phrase of perception's introduction
# dialogue (perception.introduction.IntroductionConfig; the `introduce` greeting of
# config/robot_functions.yaml asks the name), checked in this order.
QUESTION_PHRASES = (("name", "your name"), ("gender", "a man or a woman"), ("age", "how old"))
GENDERS = ("female", "male")


TOP_KEYS = ("name", "world", "household", "graph", "planner", "timeout_s", "day_start",
            "finish_own", "visitors", "requests")
REQUEST_KEYS = ("time", "person", "text", "spoken")
VISITOR_KEYS = ("name", "gender", "age", "ip", "answers")


class ScenarioError(config_file.ConfigError):
    """A scenario file that cannot be played; the message names the file and the entry."""


@dataclass(frozen=True)
class Request:
    time_s: float        # when the person speaks [s of simulated time]
    person: str          # household member (config/household.yaml)
    ip: str              # their phone IP
    text: str            # what they say
    spoken: bool = False  # True: synthesised audio through the STT node
    visitor: bool = False  # True: sent only once the person is registered (a visitor)


@dataclass(frozen=True)
class Visitor:
    """A person of the world the household does not know; the robot meets them (§3.2.3)."""

    name: str            # the name they give
    gender: str          # "female" | "male"
    age: int             # [years]
    ip: str              # their phone, which their answers and requests come from
    place: str           # graph place of their pose in the world
    answers: dict        # "name" | "gender" | "age" -> the sentence they say


@dataclass(frozen=True)
class Move:
    time_s: float        # when the person starts walking [s of simulated time]
    person: str
    place: str           # graph place of the destination pose
    activity: str
    shirt: tuple = None  # the shirt they put on there ((r, g, b) x 3); None = same clothes

    @property
    def clothes(self):
        return self.shirt is not None


@dataclass(frozen=True)
class Scenario:
    name: str
    world: Path          # sim2d world file
    graph: Path          # semantic graph of the world's map (places by region)
    requests: tuple      # Request, in time order
    moves: tuple         # Move, in time order (the world's timed moves, unannounced)
    initial: dict        # person -> (place, activity) at t = 0, from the world
    timeout_s: float     # give up this long after the last request [s of simulated time]
    planner: str         # task planner of the executor (planner_registry, EXECUTOR)
    visitors: tuple = ()  # Visitor
    day_start_s: float = 0.0  # time of day at simulated time 0 [s since midnight] (schedules)
    shirts: dict = None  # person -> the shirt they wear at t = 0 ((r, g, b) x 3), from the world
    finish_own: bool = False  # the run also waits for the robot's own instructions open when
    #                           the last request is served


def place_of(graph_spec, x, y):
    """Name of the graph place whose region contains (x, y) [m]; "" when none does."""
    for node in graph_spec["nodes"]:
        if Polygon(node["region"]).contains_point((x, y)):
            return node["name"]
    return ""


def world_shirt(value):
    """A world file's shirt_colour ([r, g, b] or {joint1, joint2, joint5}) -> ((r, g, b) x 3)."""
    if isinstance(value, dict):
        return tuple(tuple(value[k]) for k in ("joint1", "joint2", "joint5"))
    return (tuple(value),) * 3


def _people_places(world, graph_spec, where):
    initial, moves, shirts = {}, [], {}
    for person in world.get("people", []):
        name = person["name"]
        place = place_of(graph_spec, *person["pose"][:2])
        if not place:
            raise ScenarioError(f"{where}: {name} starts at {person['pose'][:2]}, in no place")
        initial[name] = (place, person.get("activity", ""))
        shirts[name] = world_shirt(person["shirt_colour"])
        for entry in person.get("schedule", []):
            place = place_of(graph_spec, *entry["pose"][:2])
            if not place:
                raise ScenarioError(f"{where}: {name}'s move at {entry['time']} s ends in no "
                                    f"place ({entry['pose'][:2]})")
            shirt = entry.get("shirt_colour")
            moves.append(Move(float(entry["time"]), name, place, entry.get("activity", ""),
                              None if shirt is None else world_shirt(shirt)))
    return initial, tuple(sorted(moves, key=lambda m: (m.time_s, m.person))), shirts


def visitor_answer(visitor, said):
    """What `visitor` answers when the robot says `said`: the answer to the first question
    (QUESTION_PHRASES) the sentence asks, "" when it asks them nothing."""
    lowered = said.lower()
    for question, phrase in QUESTION_PHRASES:
        if phrase in lowered:
            return visitor.answers[question]
    return ""


def resident_answer(person, said):
    """What a resident in new clothes answers when the robot says `said`: their name when it
    asks for it, yes or no when it asks back whether it heard a name right ("Did you say
    Carol?", perception's IntroductionConfig.confirm_question), "" otherwise."""
    lowered = said.lower()
    asked_back = re.search(r"did you say ([a-z][a-z' -]*)\?", lowered)
    if asked_back:
        return "Yes." if asked_back.group(1).strip() == person.lower() else "No."
    return f"My name is {person}." if dict(QUESTION_PHRASES)["name"] in lowered else ""



# What the robot asks someone it cannot tell (perception.identity_question.QuestionConfig)
IDENTITY_QUESTION = "Excuse me, are you {name}?"
CALL = "{name}, are you here?"
ASKED_WHO = re.compile(r"excuse me, are you ([a-z][a-z'-]*)\?")   # not "are you a man or ..."
CALLED = re.compile(r"([a-z][a-z'-]*), are you here\?")
FACING_M = 4.0    # [m] the person the robot asks stands at most this far from it


def identity_answer(person, said):
    """What `person` answers when the robot says `said`: "Yes." to "are you PERSON?", "No." to
    "are you SOMEONE-ELSE?", "Yes." to "PERSON, are you here?" (nothing to someone else's
    name), "" when the sentence asks no such thing."""
    lowered = said.lower()
    called = CALLED.search(lowered)
    if called:
        return "Yes." if called.group(1) == person.lower() else ""
    asked = ASKED_WHO.search(lowered)
    if not asked:
        return ""
    return "Yes." if asked.group(1).strip() == person.lower() else "No."


def faced_person(robot, positions):
    """The person the robot at `robot` (x, y, yaw) faces: of `positions` ({name: (x, y)}, the
    people in its place), the one nearest its heading within FACING_M, or None."""
    x, y, yaw = robot
    best = None
    for name, (px, py) in positions.items():
        if math.hypot(px - x, py - y) > FACING_M:
            continue
        off = abs(math.remainder(math.atan2(py - y, px - x) - yaw, math.tau))
        if best is None or off < best[0]:
            best = (off, name)
    return None if best is None else best[1]


def person_asked(said, robots, people, place):
    """Who answers the robot's identity question `said`: to "NAME, are you here?" NAME when in
    a robot's place, to "Excuse me, are you NAME?" the person a robot faces in its place
    (faced_person); None when nobody does. `robots`: their (x, y, yaw), `people`: {name:
    (x, y)}, `place`: (x, y) -> place name."""
    called = CALLED.search(said.lower())
    places = [place(x, y) for x, y, _ in robots]
    if called:
        return next((name for name, xy in people.items()
                     if name.lower() == called.group(1) and place(*xy) in places), None)
    for robot, here in zip(robots, places):
        person = faced_person(robot, {name: xy for name, xy in people.items()
                                      if place(*xy) == here})
        if person is not None:
            return person
    return None


# The introduce instruction's text and the dialogue's give-up sentence (perception.introduction:
# NewcomerWatch._introduce, IntroductionConfig.give_up): who is being met, and when it ended.
INTRODUCE_TEXT = "meet the unknown person"
GIVE_UP_PHRASE = "try again later"
# what the robot says when an introduction dialogue ends (perception.introduction
# IntroductionConfig: welcome, recalled, give_up): whoever answered is done
DIALOGUE_END_PHRASES = ("nice to meet you", "i will know you in these clothes now",
                        GIVE_UP_PHRASE)


def ends_dialogue(said):
    """Whether the robot's sentence `said` ends an introduction dialogue."""
    return any(phrase in said.lower() for phrase in DIALOGUE_END_PHRASES)


SEEN_SHIRT = re.compile(r"\((\d+), (\d+), (\d+)\)")


def seen_shirt(text):
    """The shirt an introduce instruction names ("meet the unknown person in bedroom (shirt
    (39, 2, 26) (42, 15, 5) (62, 0, 31))", perception.introduction) -> ((r, g, b) x 3), or None."""
    found = SEEN_SHIRT.findall(text)
    return tuple(tuple(int(c) for c in rgb) for rgb in found[:3]) if len(found) >= 3 else None


def who_answers(seen, wearing):
    """Of the people in the robot's place ({name: the shirt they wear}), the one the robot is
    asking: whose shirt is nearest (Eq. 3-10, joints 1, 2, 5) to the shirt it saw (`seen`, None
    when not known: the first of them)."""
    from human_db.colour import mean_shirt_distance
    if not wearing:
        return None
    if seen is None:
        return next(iter(wearing))
    return min(wearing, key=lambda name: mean_shirt_distance(seen, wearing[name]))


def residents(scenario):
    """The people of the world who live in the household (not visitors), in world order."""
    visitors = {v.name for v in scenario.visitors}
    return tuple(name for name in scenario.initial if name not in visitors)


def _visitors(spec, world, graph_spec, household_names, where):
    poses = {p["name"]: p["pose"] for p in world.get("people", [])}
    visitors = []
    for k, entry in enumerate(spec.get("visitors") or []):
        what = f"{where}: visitor {k + 1}"
        config_file.check_keys(entry, VISITOR_KEYS, what, ScenarioError)
        name = entry.get("name")
        if name not in poses:
            raise ScenarioError(f"{what}: {name!r} is not a person of the world")
        if name in household_names:
            raise ScenarioError(f"{what}: {name} is in the household; a visitor is someone the "
                                f"robot has not met")
        answers = entry.get("answers")
        if not isinstance(answers, dict) or sorted(answers) != ["age", "gender", "name"] or \
                not all(isinstance(a, str) and a.strip() for a in answers.values()):
            raise ScenarioError(f"{what}: answers must give a sentence for each of name, gender "
                                f"and age, got {answers!r}")
        if entry.get("gender") not in GENDERS or not isinstance(entry.get("age"), int):
            raise ScenarioError(f"{what}: gender must be female or male and age an integer, got "
                                f"{entry.get('gender')!r}, {entry.get('age')!r}")
        if not entry.get("ip"):
            raise ScenarioError(f"{what}: {name} needs the ip of their phone")
        visitors.append(Visitor(name, entry["gender"], entry["age"], str(entry["ip"]),
                                place_of(graph_spec, *poses[name][:2]), dict(answers)))
    return tuple(visitors)


def _request(entry, ips, visitors, where):
    config_file.check_keys(entry, REQUEST_KEYS, where, ScenarioError)
    person, text, time_s = entry.get("person"), str(entry.get("text", "")).strip(), \
        entry.get("time")
    if person not in ips:
        raise ScenarioError(f"{where}: unknown person {person!r} (household and visitors: "
                            f"{', '.join(sorted(ips))})")
    if not text:
        raise ScenarioError(f"{where}: empty text")
    if not isinstance(time_s, (int, float)) or time_s < 0:
        raise ScenarioError(f"{where}: time must be a number of seconds >= 0, got {time_s!r}")
    return Request(float(time_s), person, ips[person], text, bool(entry.get("spoken", False)),
                   visitor=person in visitors)


def load_scenario(path):
    """Read and check a scenario file. Its `world`, `graph` and `household` paths are found next
    to the file, else among the workspace's scenarios (config/scenarios/), so a scenario copied
    out of the workspace runs as it is."""
    path = Path(path)
    spec = config_file.read_yaml(path, ScenarioError, "scenario file")
    config_file.check_keys(spec, TOP_KEYS, str(path), ScenarioError)
    for key in ("world", "household", "graph", "requests"):
        if key not in spec:
            raise ScenarioError(f"{path}: missing '{key}'")
    world_path, graph_path, household_path = (_named_file(spec, key, path)
                                              for key in ("world", "graph", "household"))
    world = config_file.read_yaml(world_path, ScenarioError, "world file")
    graph_spec = config_file.read_yaml(graph_path, ScenarioError, "graph file")
    try:
        ips = {human.name: human.ip for human in load_household(household_path)[1]}
    except InvalidHuman as error:
        raise ScenarioError(str(error)) from None
    visitors = _visitors(spec, world, graph_spec, set(ips), path)
    ips.update({v.name: v.ip for v in visitors})
    if not isinstance(spec["requests"], list):
        raise ScenarioError(f"{path}: requests must be a list, got {spec['requests']!r}")
    requests = [_request(entry, ips, {v.name for v in visitors}, f"{path}: request {k + 1}")
                for k, entry in enumerate(spec["requests"])]
    if not requests:
        raise ScenarioError(f"{path}: no requests")
    initial, moves, shirts = _people_places(world, graph_spec, world_path)
    unknown = sorted(set(initial) - set(ips))
    if unknown:
        raise ScenarioError(f"{world_path}: people neither in the household nor visitors: "
                            f"{', '.join(unknown)}")
    timeout_s = spec.get("timeout_s", 600.0)
    if not isinstance(timeout_s, (int, float)) or timeout_s <= 0:
        raise ScenarioError(f"{path}: timeout_s must be a number of seconds > 0, got "
                            f"{timeout_s!r}")
    planner = str(spec.get("planner", "seed"))
    if planner not in PLANNERS:
        raise ScenarioError(f"{path}: planner: unknown planner {planner!r} (known: "
                            f"{', '.join(PLANNERS)})")
    day_start_s = clock_seconds(spec.get("day_start", "00:00"), f"{path}: day_start")
    finish_own = spec.get("finish_own", False)
    if not isinstance(finish_own, bool):
        raise ScenarioError(f"{path}: finish_own must be true or false, got {finish_own!r}")
    return Scenario(name=str(spec.get("name", path.stem)), world=world_path, graph=graph_path,
                    requests=tuple(sorted(requests, key=lambda r: r.time_s)), moves=moves,
                    initial=initial, timeout_s=float(timeout_s), planner=planner,
                    visitors=visitors, day_start_s=day_start_s, shirts=shirts,
                    finish_own=finish_own)


def _named_file(spec, key, path):
    """The file a scenario's `key` names: next to the scenario, else among the workspace's
    scenarios; ScenarioError names the key and where it looked."""
    found = config_file.find_file(str(spec[key]), path.parent, resource("config", "scenarios"))
    if found is None:
        raise ScenarioError(f"{path}: {key}: {spec[key]!r} is neither next to the scenario nor "
                            f"among the workspace's scenarios ({resource('config', 'scenarios')})")
    return found


def clock_seconds(text, where):
    """'HH:MM' or 'HH:MM:SS' -> seconds since midnight; ScenarioError names `where` otherwise."""
    match = re.fullmatch(r"(\d{1,2}):(\d{2})(?::(\d{2}))?", str(text))
    hours, minutes, seconds = (int(g or 0) for g in match.groups()) if match else (99, 0, 0)
    if hours > 23 or minutes > 59 or seconds > 59:
        raise ScenarioError(f"{where}: expected a quoted time of day 'HH:MM[:SS]', got {text!r}")
    return float(hours * 3600 + minutes * 60 + seconds)


def timeline(scenario):
    """Every scripted event in time order: (time [s], kind 'request' | 'move', the event)."""
    events = [(r.time_s, "request", r) for r in scenario.requests]
    events += [(m.time_s, "move", m) for m in scenario.moves]
    return sorted(events, key=lambda e: (e[0], e[1] == "request"))
