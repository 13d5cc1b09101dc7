"""The node's ROS-free session: start, steps, the end of a sentence, refusals, time limit,
a failing control step."""
import math

import numpy as np
import pytest

from semantic_nav.follow_session import (ABORTED, SUCCEEDED, FollowSession, InstructionRefused,
                                         step_failed)
from semantic_nav.follower import FollowerCommand, UnknownInstructionError
from semantic_nav.splitting import split_instruction
from semantic_nav.laser_layer import model_from_scan
from semantic_nav.word_vectors import WordVectors


class ScriptedFollower:
    """Goes at 0.3 m/s for `steps` steps per simple instruction, then reports done."""

    control_period = 0.1

    def __init__(self, classes, steps=3):
        self.classes, self.steps, self.calls = classes, steps, 0

    def start(self, sentence):
        if "flibber" in sentence:
            raise ValueError("unknown words: flibber")
        if "blorp" in sentence:
            raise UnknownInstructionError("reads with only 0.40 confidence", ["blorp"])
        self.calls = 0
        self.instructions = split_instruction(sentence)
        return self.classes

    def step(self, ranges, laser):
        index = min(self.calls // self.steps, len(self.classes) - 1)
        done = self.calls >= self.steps * len(self.classes)
        self.calls += 1
        return FollowerCommand(0.0 if done else 0.3, 0.1, index, self.classes[index], done)


LASER = model_from_scan("utm", -2.35, 0.0043633, 1081)


def test_two_part_sentence_runs_to_success():
    session = FollowSession(ScriptedFollower([1, 3]), "go straight to the end, then turn left",
                            now=0.0, max_duration=60.0)
    assert session.parts == ["go straight to the end", "turn left"]
    seen = []
    for k in range(10):
        v, w, feedback = session.step([1.0] * 1081, LASER, now=0.1 * k)
        seen.append((feedback.index, feedback.text, feedback.instruction_class))
        if session.outcome:
            break
    assert seen[0] == (0, "go straight to the end", 1)
    assert seen[3] == (1, "turn left", 3)
    assert session.outcome.status == SUCCEEDED and session.outcome.completed == 2
    assert session.outcome.spoken == "I have arrived."    # announced: the person hears "done"
    assert (v, w) == (0.0, 0.0) and len(seen) == 7
    assert math.isnan(feedback.confidence)
    assert feedback.corners == -1           # a follower without the corner count


def test_feedback_reports_the_corner_count_of_a_count_input_follower():
    class CountingFollower(ScriptedFollower):
        def step(self, ranges, laser):
            command = super().step(ranges, laser)
            return FollowerCommand(command.v, command.w, command.index,
                                   command.predicted_class, command.done, corners=self.calls)

    session = FollowSession(CountingFollower([7]), "turn right at the third corner", 0.0, 60.0)
    counts = [session.step([1.0] * 1081, LASER, now=0.1 * k)[2].corners for k in range(3)]
    assert counts == [1, 2, 3]


def test_unknown_words_and_empty_sentences_are_refused():
    with pytest.raises(InstructionRefused, match="flibber"):
        FollowSession(ScriptedFollower([1]), "flibber wibble", 0.0, 60.0)
    with pytest.raises(InstructionRefused, match="no words"):
        FollowSession(ScriptedFollower([1]), " , . ", 0.0, 60.0)


def test_time_limit_and_stop_abort_with_progress():
    session = FollowSession(ScriptedFollower([1, 3], steps=1000), "go on, then turn left", 5.0,
                            max_duration=2.0)
    assert session.step([1.0] * 1081, LASER, 6.0)[:2] == (0.3, 0.1)
    assert session.step([1.0] * 1081, LASER, 7.5)[:2] == (0.0, 0.0)
    assert session.outcome.status == ABORTED and "not finished after 2 s" in \
        session.outcome.message
    assert session.outcome.spoken == ("Sorry, I could not finish following your directions in 2 "
                                      "seconds. I am staying here.")
    other = FollowSession(ScriptedFollower([1, 3], steps=2), "go on, then turn left", 0.0, 60.0)
    for k in range(3):
        other.step([1.0] * 1081, LASER, 0.1 * k)
    outcome = other.stop("preempted")
    assert (outcome.status, outcome.completed, outcome.message) == (ABORTED, 1, "preempted")
    assert outcome.spoken == ""    # stopped from outside: whoever stopped it knows


class RecordingFollower(ScriptedFollower):
    """Remembers whether it was started."""

    def start(self, sentence):
        self.started = True
        return super().start(sentence)


def test_a_corner_beyond_the_third_is_refused_before_the_follower_starts():
    follower = RecordingFollower([7])
    with pytest.raises(InstructionRefused) as caught:
        FollowSession(follower, "turn left at the 99th corner", now=0.0, max_duration=60.0)
    assert str(caught.value).startswith("cannot follow 'turn left at the 99th corner': 'turn "
                                        "left at the 99th corner' asks for the 99th corner")
    assert caught.value.spoken == ("Sorry, I can only count corners up to the third one, and "
                                   "you asked for the 99th. I am staying here.")
    assert not hasattr(follower, "started")


def test_a_sentence_that_is_not_english_is_refused_with_the_followers_vectors():
    follower = RecordingFollower([1])
    follower.word_vectors = WordVectors(["the", "to", "go", "end"], np.zeros((4, 2)), "ranked")
    with pytest.raises(InstructionRefused) as caught:
        FollowSession(follower, "gehe geradeaus bis zum ende", now=0.0, max_duration=60.0)
    assert caught.value.spoken == ("Sorry, I can only follow directions in English. I am "
                                   "staying here.")
    assert not hasattr(follower, "started")
    FollowSession(follower, "go to the end", now=0.0, max_duration=60.0)
    assert follower.started


def test_unknown_words_get_a_spoken_reason_too():
    with pytest.raises(InstructionRefused) as caught:
        FollowSession(ScriptedFollower([1]), "flibber", now=0.0, max_duration=60.0)
    assert caught.value.spoken == ("Sorry, I did not understand those directions. I am staying "
                                   "here.")


def test_a_raising_step_fails_the_session_with_its_progress_and_a_spoken_reason():
    class BrokenFollower(ScriptedFollower):
        def step(self, ranges, laser):
            if self.calls == 4:
                raise RuntimeError("network exploded")
            return super().step(ranges, laser)

    session = FollowSession(BrokenFollower([1, 3], steps=2), "go on, then turn left", 0.0, 60.0)
    with pytest.raises(RuntimeError) as caught:
        for k in range(10):
            session.step([1.0] * 1081, LASER, 0.1 * k)
    assert session.outcome is None          # the node ends it: FollowSession.fail
    outcome = session.fail(caught.value)
    assert session.outcome is outcome
    assert (outcome.status, outcome.completed, outcome.message) == (
        ABORTED, 1, "control step failed: RuntimeError: network exploded")
    assert outcome.spoken == ("Sorry, I had to stop following your directions: my controller "
                              "failed (RuntimeError: network exploded). I am staying here.")
    assert step_failed(KeyError("x")).message == "control step failed: KeyError: 'x'"
    assert step_failed(KeyError("x")).completed == 0


def test_a_refusal_for_unknown_words_says_which_words():
    with pytest.raises(InstructionRefused) as refused:
        FollowSession(ScriptedFollower([3]), "turn blorp left", now=0.0, max_duration=60.0)
    assert refused.value.spoken == "Sorry, I did not understand 'blorp'. I am staying here."
    assert "0.40 confidence" in str(refused.value)
