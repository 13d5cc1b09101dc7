"""Asking someone the camera cannot tell whether they are the person the robot looks for
(ROS-free).

Thesis 000 §3.2.3 identifies people by their shirt colours and asks when it cannot: a resident in
new clothes is met again by name. A person seen with their shirt half hidden by a chair, or under
a light that shifts its colours, cannot be told either, and looking longer does not help; the
robot then asks the person it faces, "Excuse me, are you Carol?", and a yes puts that person at
the robot's place in human_db (the executor's belief follows). A person the camera does not see
at all where they are expected (seated behind a table) is called: "Bob, are you here?". A no, an
answer it cannot read twice or silence until `ask_timeout` leave the belief as it was.

A yes to "are you Carol?" from a person the camera saw as a stranger means Carol's clothes
changed (§3.2.3: the system "needs to update once the human changes his/her clothes"): when the
camera saw exactly one stranger at that place in the last seconds (`RecentStrangers`), their
shirt becomes Carol's. Two strangers there, or none seen whole, leave the shirt as it was: the
robot never guesses whose shirt it saw.
"""
from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np
from human_db.colour import mean_shirt_distance

from perception.answers import AnswerError, parse_yes_no

ASKED, YES, NO, UNANSWERED = "asked", "yes", "no", "unanswered"


@dataclass(frozen=True)
class QuestionConfig:
    question: str = "Excuse me, are you {name}?"
    call: str = "{name}, are you here?"
    thanks: str = "Thank you, {name}."
    mistaken: str = "I am sorry, I took you for someone else."
    ask_timeout: float = 15.0   # [s] without a yes or a no: nobody answered
    max_retries: int = 1           # re-asks after an answer that is neither yes nor no
    transcript_wait: float = 15.0  # [s] of the wall clock: how long the transcript of an
    #                                answer spoken in time is waited for once the STT node
    #                                queued it (PendingTranscripts): speech-to-text takes
    #                                seconds on a busy machine, whatever the simulator's speed

    def __post_init__(self) -> None:
        if not self.ask_timeout > 0 or self.max_retries < 0 or not self.transcript_wait >= 0:
            raise ValueError(f"~ask_timeout must be > 0, max_retries >= 0 and "
                             f"~transcript_wait >= 0, got {self.ask_timeout}, "
                             f"{self.max_retries} and {self.transcript_wait}")


@dataclass(frozen=True)
class Reply:
    """What the question does after an answer or a tick."""

    say: str = ""        # sentence for /robot/say ("" = nothing)
    state: str = ASKED   # the question's state afterwards


class IdentityQuestion:
    """One "are you NAME?" to the person the robot faces at `place`, asked at `asked_at` [s]
    (with `call`: "NAME, are you here?" to the place)."""

    def __init__(self, config: QuestionConfig, name: str, place: str, asked_at: float,
                 call: bool = False) -> None:
        if not name.strip() or not place.strip():
            raise ValueError(f"an identity question needs a name and a place, got "
                             f"{name!r} at {place!r}")
        self.config, self.name, self.place, self.call = config, name, place, call
        self.started = self.asked_at = asked_at
        self.state, self.retries = ASKED, 0

    @property
    def open(self) -> bool:
        return self.state == ASKED

    def question(self) -> str:
        return (self.config.call if self.call else self.config.question).format(name=self.name)

    def hear(self, text: str, now: float) -> Reply:
        """The person's answer -> YES (thanks), NO (an apology) or a re-ask; UNANSWERED after
        `max_retries` answers that are neither."""
        if not self.open:
            raise RuntimeError(f"the question to {self.name} is {self.state}; no answer expected")
        try:
            yes = parse_yes_no(text)
        except AnswerError as error:
            if self.retries >= self.config.max_retries:
                self.state = UNANSWERED
                return Reply(f"Sorry, {error}.", UNANSWERED)
            self.retries, self.asked_at = self.retries + 1, now
            return Reply(f"Sorry, {error}. {self.question()}", ASKED)
        self.state = YES if yes else NO
        return Reply(self.config.thanks.format(name=self.name) if yes else self.config.mistaken,
                     self.state)

    def tick(self, now: float, transcribing: Iterable[float] = ()) -> Reply:
        """UNANSWERED once `ask_timeout` passed since the question without an answer, unless
        an answer spoken in time is still being transcribed (`transcribing`: when the
        utterances heard and still awaited were spoken [s], PendingTranscripts.spoken)."""
        waited = now - self.asked_at
        if not self.open or waited < self.config.ask_timeout:
            return Reply("", self.state)
        if not transcript_on_the_way(transcribing, self.asked_at,
                                     self.asked_at + self.config.ask_timeout):
            self.state = UNANSWERED
        return Reply("", self.state)


def transcript_on_the_way(transcribing: Iterable[float], asked_at: float,
                          spoken_by: float) -> bool:
    """Whether a question asked at `asked_at` [s] waits on for a transcript: an utterance
    spoken between `asked_at` and `spoken_by` still has none (`transcribing`: when those
    heard and still awaited were spoken [s])."""
    return any(asked_at <= t <= spoken_by for t in transcribing)


class PendingTranscripts:
    """Utterances of the robot's microphone heard but not transcribed yet: when each was spoken
    [s] (the stamp the transcript will carry), awaited for `wait_s` after it was heard and
    forgotten then (the STT node refused or lost it). `heard` and `spoken` take the time on
    the clock the wait runs on: the introduction node's is the wall clock, since transcription is
    computation, as slow in simulated seconds as the simulator is fast (at 20x one transcript
    on a busy machine took 37 s of simulated time)."""

    def __init__(self, wait_s: float) -> None:
        self.wait_s = wait_s
        self._heard: dict[float, float] = {}   # spoken [s] -> when it was heard [s]

    def heard(self, spoken: float, now: float) -> None:
        self._heard[spoken] = now

    def transcribed(self, spoken: float) -> None:
        self._heard.pop(spoken, None)

    def spoken(self, now: float) -> list[float]:
        """When the utterances still awaited at `now` (heard within `wait_s`) were spoken [s]."""
        for stamp, came in list(self._heard.items()):
            if now - came >= self.wait_s:
                del self._heard[stamp]
        return list(self._heard)


@dataclass
class RecentStrangers:
    """Shirts of the unidentified people the camera saw whole, per place, over the last
    `window_s` seconds; `one_at` names the shirt when they were one person there."""

    window_s: float = 10.0      # [s] sightings this recent count
    threshold: float = 200.0    # mean Eq. 3-10 distance below which two shirts are one person
    seen: deque = field(default_factory=lambda: deque(maxlen=500))

    def __post_init__(self) -> None:
        if not self.window_s > 0:
            raise ValueError(f"~recall_window must be > 0 [s]; got {self.window_s}")

    def add(self, stamp: float, place: str, colours: np.ndarray) -> None:
        self.seen.append((stamp, place, np.asarray(colours)))

    def one_at(self, place: str, now: float) -> np.ndarray | None:
        """The latest shirt seen at `place` within the window when every recent sighting there
        is that shirt (within `threshold`); None when nobody or more than one person was seen."""
        here = [c for t, p, c in self.seen if p == place and now - self.window_s <= t <= now]
        if not here:
            return None
        latest = here[-1]
        if any(mean_shirt_distance(latest, c) >= self.threshold for c in here):
            return None
        return latest
