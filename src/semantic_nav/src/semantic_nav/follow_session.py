"""One instruction being followed by the node: the follower, its progress and how it ends.

ROS-free so the node (ros_follower.py) stays thin: the node feeds scans and the clock, sends
the (v, ω) it gets back and reports the feedback and the outcome. A control step that raises
ends the sentence too (`step_failed`, `FollowSession.fail`): aborted, with the reason in full and
in one spoken sentence. A sentence that ends by itself is announced as well: completed ("I have
arrived."), or not finished in time (the reason); one stopped from outside (preempted, replaced)
is not.

When the follower is not sure of what it read (asking_back.unsure_reasons: a low Z_w
confidence, a misheard or unknown word), the session starts by asking: `question` is said, the
robot stands still, and `answer` takes the person's reply. A yes starts the drive (its time limit
from then); a no or no answer within AskConfig.answer_timeout ends the sentence without moving.
"""
import math
from dataclasses import dataclass

import numpy as np

from supervision.health import fault_text

from semantic_nav.asking_back import NO, YES, AskConfig, question, unsure_reasons
from semantic_nav.follower import DirectionFollower, FollowerCommand, UnknownInstructionError
from semantic_nav.instruction_layer import UnfollowableInstruction, check_followable
from semantic_nav.laser_layer import LaserModel
from semantic_nav.splitting import InstructionError

SUCCEEDED, ABORTED = "succeeded", "aborted"
ARRIVED = "I have arrived."   # said when a sentence is completed
DECLINED = "All right, I am staying here. Please tell me the directions again."
UNANSWERED = "I heard no answer, so I am staying here."
STOPPED = "All right, I have stopped."


@dataclass
class Feedback:
    index: int               # simple instruction being followed (0-based)
    text: str                # its words
    instruction_class: int   # class the network predicts for it (1..10)
    confidence: float        # its softmax probability (NaN when the follower gives none)
    corners: int = -1        # corners counted so far in it (-1: no count-input network)


@dataclass
class Outcome:
    status: str              # SUCCEEDED | ABORTED
    completed: int           # simple instructions completed
    message: str
    spoken: str = ""         # the reason said to the person ("": nothing to say)


def step_failed(error: BaseException, completed: int = 0) -> Outcome:
    """Outcome of a sentence whose control step raised `error` (also while it was being
    started): aborted, the fault named in the message and in the spoken sentence."""
    text = fault_text(error)
    return Outcome(ABORTED, completed, f"control step failed: {text}",
                   f"Sorry, I had to stop following your directions: my controller failed "
                   f"({text}). I am staying here.")


class InstructionRefused(ValueError):
    """The sentence cannot be followed (no words, unknown words, a corner beyond the third, not
    English); str() says why in full, `spoken` says it to the person in one sentence."""

    def __init__(self, message: str, spoken: str) -> None:
        super().__init__(message)
        self.spoken = spoken


class FollowSession:
    """Follow one sentence: start it, step it once per control period, end it."""

    def __init__(self, follower: DirectionFollower, sentence: str, now: float,
                 max_duration: float) -> None:
        """Raises InstructionRefused for a sentence the follower cannot take or must not try
        (instruction_layer.check_followable, with the follower's word vectors if it has any),
        before the follower is started: the robot does not move."""
        try:
            check_followable(sentence, getattr(follower, "word_vectors", None))
            self.classes = list(follower.start(sentence))
            self.parts = list(follower.instructions)    # the simple instructions it follows
        except UnfollowableInstruction as error:
            raise InstructionRefused(f"cannot follow {sentence!r}: {error}",
                                     error.spoken) from error
        except UnknownInstructionError as error:
            heard = " ".join(error.words)
            spoken = (f"Sorry, I did not understand {heard!r}. I am staying here." if heard
                      else "Sorry, I did not understand those directions. I am staying here.")
            raise InstructionRefused(f"cannot follow {sentence!r}: {error}", spoken) from error
        except (InstructionError, ValueError) as error:
            raise InstructionRefused(f"cannot follow {sentence!r}: {error}",
                                     "Sorry, I did not understand those directions. I am "
                                     "staying here.") from error
        self.follower, self.sentence = follower, sentence
        self.started, self.max_duration = now, max_duration
        self.index = 0
        self.outcome: Outcome | None = None
        self.ask = getattr(getattr(follower, "config", None), "ask", None) or \
            AskConfig(enabled=False)
        self.unsure = unsure_reasons(getattr(follower, "confidences", []),
                                     getattr(follower, "corrections", []),
                                     getattr(follower, "unknown_words", []), self.ask)
        # what the robot asks before it drives ("" = it drives at once)
        self.question = question(self.classes, getattr(follower, "countings", None)) \
            if self.unsure else ""
        self.asking = bool(self.question)

    def wait(self, now: float) -> Feedback:
        """A control period spent waiting on the answer to the question (the robot stands
        still); sets self.outcome when none came within AskConfig.answer_timeout."""
        if now - self.started > self.ask.answer_timeout:
            self.outcome = Outcome(ABORTED, 0, f"not followed: no answer to {self.question!r} "
                                   f"in {self.ask.answer_timeout:.0f} s", UNANSWERED)
        return self.feedback()

    def answer(self, reply: str, now: float) -> None:
        """A yes or a no heard (asking_back.YES / NO). To the question: a yes starts the drive
        (the time limit counts from now), a no ends the sentence without moving. While the
        robot drives: a no stops it, a yes changes nothing."""
        if reply not in (YES, NO):
            raise ValueError(f"an answer is {YES!r} or {NO!r}, got {reply!r}")
        if not self.asking:
            if reply == NO:
                self.stop("stopped: the person said no", STOPPED)
        elif reply == YES:
            self.asking, self.started = False, now
        else:
            self.outcome = Outcome(ABORTED, 0, f"not followed: the answer to {self.question!r} "
                                   "was no", DECLINED)

    def feedback(self, command: FollowerCommand | None = None) -> Feedback:
        index = min(self.index, len(self.classes) - 1)
        predicted = command.predicted_class if command is not None else self.classes[index]
        # DirectionFollower: Z_w's largest probability per part (before any one-hot)
        confidences = getattr(self.follower, "confidences", None)
        confidence = float(confidences[index]) if confidences and index < len(confidences) \
            else math.nan
        text = self.parts[index] if index < len(self.parts) else ""
        corners = getattr(command, "corners", None)
        return Feedback(index, text, int(predicted), float(confidence),
                        -1 if corners is None else int(corners))

    def step(self, ranges: np.ndarray, laser: LaserModel,
             now: float) -> tuple[float, float, Feedback]:
        """One control step -> (v, w); sets self.outcome when the sentence is done or too long.
        Not while a question waits on its answer (`wait`)."""
        if self.asking:
            raise RuntimeError("FollowSession.step while asking: the robot waits on a yes")
        if now - self.started > self.max_duration:
            self.outcome = Outcome(ABORTED, self.index,
                                   f"not finished after {self.max_duration:.0f} s",
                                   f"Sorry, I could not finish following your directions in "
                                   f"{self.max_duration:.0f} seconds. I am staying here.")
            return 0.0, 0.0, self.feedback()
        command = self.follower.step(ranges, laser)
        self.index = int(command.index)
        if command.done:
            self.outcome = Outcome(SUCCEEDED, len(self.classes),
                                   f"completed {len(self.classes)} simple instruction(s)",
                                   ARRIVED)
            return 0.0, 0.0, self.feedback(command)
        return float(command.v), float(command.w), self.feedback(command)

    def stop(self, reason: str, spoken: str = "") -> Outcome:
        """Ended from outside (preempted, replaced, shut down, a person's no) -> Outcome;
        `spoken`: what to say ("" = nothing)."""
        self.outcome = Outcome(ABORTED, self.index, reason, spoken)
        return self.outcome

    def fail(self, error: BaseException) -> Outcome:
        """The control step raised `error` -> Outcome (aborted; step_failed)."""
        self.outcome = step_failed(error, self.index)
        return self.outcome
