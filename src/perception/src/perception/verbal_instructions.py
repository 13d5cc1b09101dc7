"""Verbal perception to instructions (thesis 000 §3.3, Fig. 3-15, §4.2.1, Table 4-1, Table 5-5).

An utterance (text + phone IP) is read for its sentiment (VADER), physical terms, requested robot
function and target person; the result becomes one instruction, or a chain linked through
`previous_id`, whose initial reward and decay follow the priority physical > negative > neutral >
positive. People are looked up through a PeopleDirectory (the human database in the ROS layer, a
dict in tests).

The instructions carry provisional ids, 1, 2, ... in chain order (task_planner.submission): the
task buffer allocates the real ones when the node submits them. Every request not taken is said
back to the speaker with the reason: one refused here (`rejection_sentence`), and one the task
planner did not take (`refusal_sentence`).
"""
from abc import ABC, abstractmethod
from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass

from task_planner.instruction import HUMAN, NAME_MAX_CHARS, Instruction
from task_planner.reward import Priority
from task_planner.robot_functions import about_text
from task_planner.submission import Submission

from perception.requests import (CAREGIVER, PRIORITY_LEVELS, KeywordConfig, RejectedUtterance,
                                 RobotFunction, check_text, extract_function,
                                 find_physical_terms, find_target)
from perception.sentiment import SentimentAnalyzer, mood_text

ANONYMOUS = "anonymous"
# An unknown phone's request is served as "anonymous@<address>", which must fit an instruction's
# source (NAME_MAX_CHARS): a longer address is refused, not a fault.
PHONE_MAX_CHARS = NAME_MAX_CHARS - len(ANONYMOUS) - 1


@dataclass(frozen=True)
class Person:
    name: str
    ip: str = ""        # phone IP
    location: str = ""  # graph place name; "" = not seen yet


class PeopleDirectory(ABC):
    """Who is who: the human database seen from verbal perception."""

    @abstractmethod
    def lookup_by_ip(self, ip: str) -> Person | None:
        """Person whose phone has this IP, or None."""

    @abstractmethod
    def lookup_by_name(self, name: str) -> Person | None:
        """Person of this name (case-insensitive), or None."""

    def location_of(self, name: str) -> str:
        """Last known place of the named person; "" when unknown."""
        person = self.lookup_by_name(name)
        return person.location if person else ""


class DictPeopleDirectory(PeopleDirectory):
    """PeopleDirectory over an in-memory list of Persons."""

    def __init__(self, people: Collection[Person]) -> None:
        self._by_name = {p.name.lower(): p for p in people}
        self._by_ip = {p.ip: p for p in people if p.ip}

    def lookup_by_ip(self, ip: str) -> Person | None:
        return self._by_ip.get(ip)

    def lookup_by_name(self, name: str) -> Person | None:
        return self._by_name.get(name.lower())


@dataclass(frozen=True)
class Interpretation:
    """Fig. 3-15: what one sentence means to the robot."""

    text: str
    compound: float        # VADER compound score
    sentiment: str         # positive / neutral / negative (§3.3)
    physical_terms: tuple  # physical terms found (§3.3)
    function: RobotFunction  # robot function requested
    keyword: str           # phrase that selected the function
    target_name: str | None  # named person, or None when the speaker is the target
    level: str             # priority level: physical / negative / neutral / positive


@dataclass(frozen=True)
class BuildResult:
    instructions: tuple  # Instructions in execution order (chain linked by previous_id)
    notes: tuple         # human-readable remarks worth logging (anonymous source, ...)


def priority_level(physical_terms: Sequence[str], sentiment: str) -> str:
    """§4.2.1: physical help outranks mood; otherwise the sentiment label is the level.

    VADER scores "I have a headache and fever" 0.0 (neutral), so physical terms must decide.
    """
    if physical_terms:
        return "physical"
    if sentiment not in PRIORITY_LEVELS:
        raise ValueError(f"unknown sentiment label {sentiment!r}")
    return sentiment


def check_phone(ip: str) -> None:
    """Refuse a phone address that cannot name a request's source: longer than PHONE_MAX_CHARS,
    or holding spaces or control characters. Raises RejectedUtterance naming the problem."""
    if len(ip) > PHONE_MAX_CHARS:
        raise RejectedUtterance(f"the phone address has {len(ip)} characters, more than the "
                                f"{PHONE_MAX_CHARS} a phone address may have")
    if not ip.isprintable() or any(c.isspace() for c in ip):
        raise RejectedUtterance(f"the phone address {ip!r} holds spaces or control characters")


def interpret(text: str, keywords: KeywordConfig, analyser: SentimentAnalyzer,
              directory: PeopleDirectory) -> Interpretation:
    """Fig. 3-15: sentiment, physical terms, requested function and target of one sentence.

    Raises RejectedUtterance for empty, over-long or non-English text, for a sentence that asks
    for no robot function, and for an unknown target name.
    """
    def canonical_name(word: str) -> str | None:
        person = directory.lookup_by_name(word)
        return person.name if person else None

    tokens = check_text(text, keywords, lambda word: canonical_name(word) is not None)
    words = [t.lower for t in tokens]
    physical = find_physical_terms(words, keywords)
    match = extract_function(words, keywords, physical)
    if match is None:
        raise RejectedUtterance(f"no robot function requested in {text!r}")
    target = find_target(tokens, keywords, canonical_name)
    sentiment = analyser.analyse(mood_text(text, keywords.sentiment_neutral_words))
    return Interpretation(text=text, compound=sentiment.compound, sentiment=sentiment.label,
                          physical_terms=physical, function=match.function, keyword=match.keyword,
                          target_name=target, level=priority_level(physical, sentiment.label))


class InstructionBuilder:
    """Table 4-1 instructions from Interpretations, with provisional ids (see above)."""

    def __init__(self, keywords: KeywordConfig, priorities: Mapping[str, Priority],
                 place_ids: Mapping[str, int], directory: PeopleDirectory) -> None:
        """Args:
            priorities: {level: task_planner.reward.Priority} (config/priorities.yaml, read by
                load_priorities) holding every level of Table 5-5 that speech can produce.
            place_ids: {graph place name: node id}.
        """
        missing = set(PRIORITY_LEVELS) - set(priorities)
        if missing:
            raise ValueError(f"priority table lacks levels {sorted(missing)}")
        if keywords.default_place not in place_ids:
            raise ValueError(f"default_place {keywords.default_place!r} is not a place of the "
                             f"graph {sorted(place_ids)}")
        self.keywords = keywords
        self.priorities = priorities
        self.place_ids = place_ids
        self.directory = directory

    def build(self, interpretation: Interpretation, ip: str, start_time: float) -> BuildResult:
        """§4.2.1: the instruction (or chain) for one interpreted utterance from phone `ip`."""
        notes: list[str] = []
        speaker = self.directory.lookup_by_ip(ip)
        if speaker is None:
            source = f"{ANONYMOUS}@{ip}" if ip else ANONYMOUS
            notes.append(f"unknown phone IP {ip!r}: request served as {source}")
            speaker = Person(name=source, ip=ip)
        function = interpretation.function
        if function.served_to == CAREGIVER:
            target = self.keywords.caregiver
        else:
            target = interpretation.target_name or speaker.name
        steps = [(function, target, interpretation.text)]
        if target != speaker.name:
            # A follow-up ("report to the care giver") is about the person the head served.
            follow_ups = self.keywords.chains.get(function.name, ())
            steps += [(self.keywords.functions[name], speaker.name,
                       about_text(target, interpretation.text)) for name in follow_ups]
        instructions, previous_id = [], 0
        for position, (step_function, person, text) in enumerate(steps, start=1):
            instruction = self._instruction(position, interpretation, step_function,
                                            speaker.name, person, previous_id, start_time, text,
                                            notes)
            instructions.append(instruction)
            previous_id = instruction.id
        return BuildResult(tuple(instructions), tuple(notes))

    def _place_of(self, name: str, notes: list[str]) -> str:
        """Graph place of the named person: their last known location, else the default place."""
        person = self.directory.lookup_by_name(name)
        location = person.location if person else ""
        if location in self.place_ids:
            return location
        why = f"last seen at unknown place {location!r}" if location else "location unknown"
        notes.append(f"{name}: {why}; serving at {self.keywords.default_place}")
        return self.keywords.default_place

    def _instruction(self, provisional_id: int, interpretation: Interpretation,
                     function: RobotFunction, source: str, person: str, previous_id: int,
                     start_time: float, text: str, notes: list[str]) -> Instruction:
        priority = self.priorities[interpretation.level]
        place = self._place_of(person, notes)
        instruction = Instruction(
            id=provisional_id, previous_id=previous_id, gamma=priority.gamma, beta=priority.beta,
            type=HUMAN, start_time=start_time, duration=function.duration_s, source=source,
            target=person, status=self.keywords.status_codes[interpretation.level],
            function=function.code, destination=self.place_ids[place], destination_name=place,
            text=text)
        return instruction


class VerbalPipeline:
    """Fig. 3-15 end to end: utterance text + phone IP -> instructions (or RejectedUtterance)."""

    def __init__(self, keywords: KeywordConfig, analyser: SentimentAnalyzer,
                 builder: InstructionBuilder, directory: PeopleDirectory) -> None:
        self.keywords = keywords
        self.analyser = analyser
        self.builder = builder
        self.directory = directory

    def process(self, text: str, ip: str,
                start_time: float) -> tuple[Interpretation, BuildResult]:
        """Returns (Interpretation, BuildResult); raises RejectedUtterance naming the problem."""
        check_phone(ip)
        interpretation = interpret(text, self.keywords, self.analyser, self.directory)
        return interpretation, self.builder.build(interpretation, ip, start_time)


def rejection_sentence(reason: str) -> str:
    """What the robot says when it does not take a spoken request, `reason` saying why."""
    return f"Sorry, I cannot take your request: {reason}"


def refusal_sentence(submission: Submission) -> str:
    """What the robot says when the task planner did not take (all of) a spoken request:
    task_planner.submission.Submission -> sentence naming the reason; "" when all was taken."""
    if submission.complete:
        return ""
    if submission.accepted:
        taken = ", ".join(str(i.id) for i in submission.accepted)
        return (f"Sorry, I could only take part of your request (as request {taken}): "
                f"{submission.refusal}")
    return rejection_sentence(submission.refusal)
