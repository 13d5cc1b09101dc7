"""Meeting a new person: the Initialization phase of thesis 000 §3.2.3.

"During the Initialization phase, the robot will approach an unknown person and greet to him or
her, asking the name, gender, and age. [...] The system then extracts and stores the RGB values on
chest, left shoulder, and right shoulder, which are joint 1, joint 2, and joint 5."

Two parts, both ROS-free:
- `NewcomerWatch` decides from visual perception's unidentified people that someone is new and
  worth meeting: all three shirt joints seen, no registered person and no stranger already being
  met within the identification threshold (Eq. 3-10, mean over joints 1, 2, 5 below 200), seen in
  `min_sightings` frames. It then gives the robot a robot-type `introduce` instruction (Table 4-1)
  for that stranger (each their own: a household that starts with nobody met has several
  strangers at once; the node holds one dialogue at a time) at the place the stranger was seen,
  with the self-generated priority and no target (the executor serves it at the place without
  looking for a known person). The instruction carries
  the provisional id 1 (task_planner.submission): the node submits it with id 0 and tells the
  watch the id the task buffer allocated (`taken`), or that it was not taken (`not_taken`).
- `IntroductionDialogue` runs the questions once the robot is there: the `introduce` function's
  greeting asks the name, then the dialogue asks the gender and the age, re-asks (boundedly) what
  it cannot read, and produces the human_db `Human` with the stranger's shirt colours and the
  phone address the answers came from, in the place where the robot met them. A name the
  household already has is a resident in new clothes (§3.2.3: the system "needs to update once
  the human changes his/her clothes"): the dialogue ends there and `recalled` names them, whose
  shirt colours the node then updates.
"""
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from human_db.colour import (IdentificationConfig, Shirt, identifies, mean_shirt_distance,
                             shirt_colours)
from human_db.model import Human
from numpy.typing import ArrayLike, NDArray
from task_planner.instruction import ROBOT, Instruction
from task_planner.reward import Priority

from perception.answers import (AnswerError, closest_name, parse_age, parse_gender, parse_name,
                                parse_yes_no)
from perception.identity_question import transcript_on_the_way

# Dialogue states: the question being waited for, then the end states.
NAME, GENDER, AGE, COMPLETE, FAILED = "name", "gender", "age", "complete", "failed"
CONFIRM = "confirm"   # "Did you say Carol?": a heard name close to a resident's
SUBMITTING = -1   # Stranger.instruction_id while their introduce instruction is being submitted


@dataclass(frozen=True)
class IntroductionConfig:
    threshold: float = 200.0       # mean ΔC (Eq. 3-10) below which two shirts are one person
    ambiguity_margin: float = 60.0  # human_db's ~ambiguity_margin: a sighting two registered
                                    # shirts fit about equally well is met (asked), not guessed
    min_sightings: int = 3         # frames a stranger is seen in before the robot goes to meet
    max_retries: int = 2           # re-asks of one question before the dialogue is given up
    answer_timeout: float = 45.0   # [s] without an answer before a question is asked again
    transcript_wait: float = 15.0  # [s] of the wall clock an answer the STT node queued
                                   # (stt/heard) is waited for (PendingTranscripts)
    retry_after: float = 300.0     # [s] a stranger not met (dialogue or trip failed) is left alone
    name_question: str = "What is your name?"
    thanks: str = "Thank you, {name}."      # said before the next question after the name
    gender_question: str = "Are you a man or a woman?"
    age_question: str = "How old are you?"
    welcome: str = "Nice to meet you, {name}."
    recalled: str = "Thank you, {name}. I will know you in these clothes now."
    confirm_question: str = "Did you say {name}?"
    name_similarity: float = 0.75  # [-] difflib ratio from which a heard name may be a resident's
    give_up: str = "I am sorry, I could not understand you. Let us try again later."
    seen_within: float = 60.0      # [s] the stranger must have been seen in the place this long
                                   # before the dialogue began, or during it, for the answers to
                                   # be theirs (else someone else answered for them)
    not_seen: str = "I am sorry, I cannot see the person I came to meet. Let us try again later."
    gone_after: float = 20.0       # [s] with nothing heard and the stranger not seen in the
                                   # place since the greeting: they walked off, the meeting
                                   # ends (0: wait for the answers' timeouts)
    pass_through: tuple = ()       # places people only pass through (an alley): a stranger
                                   # there is met only once seen there `settle_after` [s]
    settle_after: float = 10.0     # [s] (walking by, they are met in the room they settle in)


@dataclass
class Stranger:
    """An unidentified person as the robot has seen them."""

    colours: np.ndarray        # (3, 3) shirt RGB at joints 1, 2, 5 of the latest sighting
    place: str                 # semantic place of the latest sighting
    first_seen: float          # [s]
    last_seen: float           # [s]
    sightings: int = 1
    place_since: float = 0.0   # [s] first sighting in `place` since they were last elsewhere
    instruction_id: int = 0    # the introduce instruction given for them (SUBMITTING until the
                               # task buffer allocated its id); 0 = none
    left_until: float = 0.0    # [s] not met again before this (after a failed meeting)
    asked_in: str = ""          # the place of their introduce instruction (where the robot
                               # meets them)
    left_in: str = ""           # the place they were left alone in: seen elsewhere, they
                               # walked off, and count again at once
    name: str = ""             # set once registered


def seen_shirt(values: Iterable[float]) -> NDArray[np.int64] | None:
    """9 uint8 (r1 g1 b1 r2 g2 b2 r5 g5 b5) -> (3, 3) array, or None when a joint was not seen
    (visual perception sends zeros then); InvalidColour names a malformed value."""
    colours = shirt_colours([int(v) for v in values], "observed shirt colour")
    return None if not colours.any() else colours


def shirts_known(known: Mapping[str, tuple[np.ndarray | None, str]],
                 doubted_as: str = "") -> list[np.ndarray]:
    """The registered shirts an unidentified sighting is checked against ({name: (shirt or
    None, phone IP)}): a sighting visual perception doubted (`doubted_as`, the person whose
    shirt it was closest to) is a stranger unless it matches someone else, such as the person
    registered in those clothes since."""
    return [colours for name, (colours, _) in known.items()
            if colours is not None and name != doubted_as]


class NewcomerWatch:
    """Unidentified people -> `introduce` instructions, one per stranger.

    Args:
        config: IntroductionConfig.
        function: (code, duration_s) of the robot function `introduce`.
        priority: task_planner.reward.Priority of the self-generated level.
        place_ids: {place name: graph node id}.
    """

    def __init__(self, config: IntroductionConfig, function: tuple[int, float], priority: Priority,
                 place_ids: Mapping[str, int]) -> None:
        self.config, self.function, self.priority = config, function, priority
        self.place_ids = place_ids
        self.identification = IdentificationConfig(config.threshold, config.ambiguity_margin)
        self.strangers: list[Stranger] = []    # in the order first seen

    def matching(self, colours: np.ndarray) -> Stranger | None:
        """The stranger whose shirt is closest to `colours` within the threshold, or None."""
        best: Stranger | None = None
        best_distance = self.config.threshold
        for stranger in self.strangers:
            distance = mean_shirt_distance(colours, stranger.colours)
            if distance < best_distance:
                best, best_distance = stranger, distance
        return best

    def open_strangers(self) -> list[Stranger]:
        """The strangers whose introduce instruction is open (or being submitted)."""
        return [s for s in self.strangers if s.instruction_id and not s.name]

    def observe(self, colours: np.ndarray | None, place: str, stamp: float,
                known: Iterable[Shirt]) -> Instruction | None:
        """One sighting of an unidentified person; returns an introduce Instruction or None.

        Args:
            colours: (3, 3) shirt RGB at joints 1, 2, 5 (seen_shirt), None when not all seen.
            place: semantic place of the sighting ("" = outside every place).
            stamp: [s] time of the sighting.
            known: iterable of (3, 3) shirt colours of the registered people.
        """
        if colours is None or not place:
            return None
        if identifies(colours, list(known), self.identification):
            return None   # identified since visual perception asked human_db
        stranger = self.matching(colours)
        if stranger is None:
            self.strangers.append(Stranger(np.array(colours), place, stamp, stamp,
                                           place_since=stamp))
            stranger = self.strangers[-1]
        else:
            moved = place != stranger.place
            if moved:
                stranger.place_since = stamp
            stranger.colours, stranger.place, stranger.last_seen = np.array(colours), place, stamp
            if stamp < stranger.left_until and place == stranger.left_in:
                return None   # left alone there: sightings count again after retry_after
            # seen in another place: walking by, met once seen min_sightings times where they are
            stranger.sightings = 1 if moved else stranger.sightings + 1
        if stranger.name or stranger.instruction_id:
            return None
        if stranger.sightings < self.config.min_sightings or passing_by(stranger, self.config):
            return None
        return self._introduce(stranger, stamp)

    def _introduce(self, stranger: Stranger, stamp: float) -> Instruction | None:
        if stranger.place not in self.place_ids:
            return None
        code, duration = self.function
        stranger.instruction_id, stranger.left_until = SUBMITTING, 0.0
        stranger.asked_in = stranger.place
        rgb = " ".join(str(tuple(int(c) for c in joint)) for joint in stranger.colours)
        return Instruction(
            id=1, gamma=self.priority.gamma, beta=self.priority.beta,
            destination=self.place_ids[stranger.place], type=ROBOT, start_time=stamp,
            duration=int(duration), source="robot", target="", function=code,
            destination_name=stranger.place,
            text=f"meet the unknown person in {stranger.place} (shirt {rgb})")

    def by_instruction(self, instruction_id: int) -> Stranger | None:
        return next((s for s in self.strangers if s.instruction_id == instruction_id), None)

    def taken(self, instruction_id: int) -> Stranger:
        """The task buffer took the introduce instruction being submitted, as `instruction_id`;
        returns its stranger."""
        stranger = self.by_instruction(SUBMITTING)
        if stranger is None:
            raise RuntimeError("no introduce instruction is being submitted")
        stranger.instruction_id = instruction_id
        return stranger

    def not_taken(self, now: float) -> Stranger:
        """The introduce instruction being submitted was not taken: leave its stranger alone for
        `retry_after`; returns the stranger."""
        stranger = self.by_instruction(SUBMITTING)
        if stranger is None:
            raise RuntimeError("no introduce instruction is being submitted")
        self.not_met(stranger, now)
        return stranger

    def registered(self, stranger: Stranger, name: str) -> None:
        """The stranger is now `name` in human_db: never introduced again."""
        stranger.name = name

    def known_as(self, colours: np.ndarray, name: str) -> int:
        """The stranger in shirt `colours` said they are `name` (a clothes change): registered
        as them -> the id of the meeting asked for them, now needless (0: none, or no such
        stranger)."""
        stranger = self.matching(colours)
        if stranger is None:
            return 0
        self.registered(stranger, name)
        return stranger.instruction_id

    def not_met(self, stranger: Stranger, now: float) -> None:
        """The meeting failed (no answers, trip failed): leave them alone for `retry_after` in
        the place the robot tried to meet them; seen in another place, they walked off before
        the robot came and are met there."""
        stranger.instruction_id, stranger.sightings = 0, 0
        stranger.left_until = now + self.config.retry_after
        stranger.left_in = stranger.asked_in or stranger.place


def answered_by_the_stranger(stranger: Stranger, place: str, started: float,
                             config: IntroductionConfig) -> bool:
    """Whether the answers of a dialogue that began at `started` [s] in `place` can be the
    stranger's: they were last seen there at most `config.seen_within` before it began, or
    during it. §3.2.3 stores the shirt of the person asked; a stranger who walked off before the
    robot came is not the one who answered (someone else in the room did)."""
    return seen_there_since(stranger, place, started - config.seen_within)


def passing_by(stranger: Stranger, config: IntroductionConfig) -> bool:
    """Whether the stranger is only passing through their place (`config.pass_through`): seen
    there for less than `settle_after` [s]. A meeting asked for a person walking down the alley
    finds nobody there."""
    return (stranger.place in config.pass_through
            and stranger.last_seen - stranger.place_since < config.settle_after)


def seen_there_since(stranger: Stranger, place: str, since: float) -> bool:
    """Whether the stranger's latest sighting was in `place`, at or after `since` [s]."""
    return stranger.place == place and stranger.last_seen >= since


def walked_off(stranger: Stranger, dialogue: "IntroductionDialogue", now: float,
               transcribing: Iterable[float] = ()) -> bool:
    """Whether the stranger of a dialogue walked off before answering: nothing was heard
    `gone_after` [s] after the greeting and perception has not seen them in the dialogue's
    place since it began. An answer takes about 5 s through the speech-to-text node (16 s on
    a loaded machine), so a silent stranger who is out of sight is not waited for to the
    end of the robot function's 60 s. An answer spoken since the greeting whose transcript
    is still on the way (`transcribing`: when the utterances heard and still awaited were
    spoken [s], PendingTranscripts.spoken) was heard: at 20x real time one transcript takes
    20 s of simulated time, and the stranger who gave it had not walked off."""
    config = dialogue.config
    waited = now - dialogue.started
    return (config.gone_after > 0 and not dialogue.heard and waited >= config.gone_after
            and not seen_there_since(stranger, dialogue.place, dialogue.started)
            and not transcript_on_the_way(transcribing, dialogue.started, now))


@dataclass(frozen=True)
class Turn:
    """What the dialogue does after an answer or a tick."""

    say: str = ""        # sentence for /robot/say ("" = nothing)
    state: str = NAME    # dialogue state afterwards


class IntroductionDialogue:
    """Name, gender and age of one stranger (§3.2.3); the greeting has already asked the name."""

    QUESTIONS = (NAME, GENDER, AGE)

    def __init__(self, config: IntroductionConfig, colours: ArrayLike, started: float,
                 place: str = "", residents: Iterable[str] = ()) -> None:
        self.config, self.colours, self.place = config, np.array(colours), place
        self.state, self.retries, self.asked_at = NAME, 0, started
        self.started = started
        self.answers: dict[str, Any] = {}     # question -> parsed value (str, or int age)
        self.ip = ""          # phone of the first answer; "" = the robot's microphone
        self.residents = {name.lower(): name for name in residents}   # registered names
        self.recalled = ""    # the resident this stranger turned out to be ("" = a new person)
        self.heard_name = ""  # CONFIRM: the name as heard, taken if the resident's is denied
        self.candidate = ""   # CONFIRM: the resident whose name it may be
        self.heard = 0        # answers heard, understood or not

    @property
    def open(self) -> bool:
        return self.state not in (COMPLETE, FAILED)

    def _question(self) -> str:
        if self.state == CONFIRM:
            return self.config.confirm_question.format(name=self.candidate)
        return {NAME: self.config.name_question, GENDER: self.config.gender_question,
                AGE: self.config.age_question}[self.state]

    def hear(self, text: str, ip: str, now: float) -> Turn:
        """One answer from the person; returns the Turn (next question, re-ask or the end)."""
        if not self.open:
            raise RuntimeError(f"dialogue is {self.state}; no answer expected")
        self.heard += 1
        reader: Callable[[str], Any] = {NAME: parse_name, GENDER: parse_gender, AGE: parse_age,
                  CONFIRM: parse_yes_no}[self.state]
        try:
            value = reader(text)
        except AnswerError as error:
            return self._ask_again(f"Sorry, {error}.", now)
        if self.state == CONFIRM:
            return self._confirmed(value, ip, now)
        if self.state == NAME and value.lower() in self.residents:
            return self._recall(self.residents[value.lower()])
        if self.state == NAME:
            candidate = closest_name(value, self.residents.values(), self.config.name_similarity)
            if candidate:   # never guess: ask whether the speech-to-text misheard a resident
                self.state, self.heard_name, self.candidate = CONFIRM, value, candidate
                self.retries, self.asked_at, self.ip = 0, now, self.ip or ip
                return Turn(self._question(), CONFIRM)
        return self._take(value, ip, now)

    def _recall(self, name: str) -> Turn:
        self.recalled = self.answers[NAME] = name
        self.state = COMPLETE
        return Turn("", COMPLETE)

    def _confirmed(self, yes: bool, ip: str, now: float) -> Turn:
        if yes:
            return self._recall(self.candidate)
        self.state = NAME       # not the resident: a new person with the name as heard
        return self._take(self.heard_name, ip, now)

    def _take(self, value: str | int, ip: str, now: float) -> Turn:
        """Record an answer to the current question and ask the next."""
        self.ip = self.ip or ip
        self.answers[self.state] = value
        self.state = self.QUESTIONS[self.QUESTIONS.index(self.state) + 1] \
            if self.state != AGE else COMPLETE
        self.retries, self.asked_at = 0, now
        if not self.open:
            return Turn("", self.state)
        if self.state == GENDER:
            return Turn(f"{self.config.thanks.format(name=value)} {self._question()}", GENDER)
        return Turn(self._question(), self.state)

    def tick(self, now: float, transcribing: Iterable[float] = ()) -> Turn:
        """Ask again after `answer_timeout` without an answer; Turn() when nothing is due. An
        answer spoken since the question and still being transcribed (`transcribing`: when the
        utterances heard and still awaited were spoken [s], PendingTranscripts.spoken) holds
        the question: asked again, the person would answer a question already answered."""
        waited = now - self.asked_at
        if not self.open or waited < self.config.answer_timeout:
            return Turn("", self.state)
        if transcript_on_the_way(transcribing, self.asked_at, now):
            return Turn("", self.state)
        return self._ask_again("Sorry, I did not hear you.", now)

    def _ask_again(self, apology: str, now: float) -> Turn:
        self.asked_at = now
        if self.retries >= self.config.max_retries:
            self.state = FAILED
            return Turn(f"{apology} {self.config.give_up}", FAILED)
        self.retries += 1
        return Turn(f"{apology} {self._question()}", self.state)

    def abort(self) -> Turn:
        """End the dialogue as FAILED from outside (the node could not go on); returns the Turn
        with the give-up sentence."""
        self.state = FAILED
        return Turn(self.config.give_up, FAILED)

    def human(self) -> Human:
        """The human_db Human to register, in the place the robot met them (raises InvalidHuman
        naming a bad field)."""
        if self.state != COMPLETE:
            raise RuntimeError(f"dialogue is {self.state}, not complete")
        return Human(name=self.answers[NAME], gender=self.answers[GENDER], age=self.answers[AGE],
                     shirt_colour=tuple(tuple(int(c) for c in j) for j in self.colours),
                     ip=self.ip, location=self.place)

    def welcome(self) -> str:
        text = self.config.recalled if self.recalled else self.config.welcome
        return text.format(name=self.answers[NAME])

    def shirt(self) -> tuple[tuple[int, ...], ...]:
        """The shirt colours ((r, g, b) x 3) the person wears now."""
        return tuple(tuple(int(c) for c in joint) for joint in self.colours)
