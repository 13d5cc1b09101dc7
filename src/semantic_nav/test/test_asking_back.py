"""Asking back: when the follower is unsure, what the robot says, how a reply is read, and the
session that waits on it (a yes drives, a no or silence never does)."""
import pytest

from semantic_nav.asking_back import (NO, YES, AskConfig, describe, question, read_answer,
                                      unsure_reasons)
from semantic_nav.follow_session import (ABORTED, DECLINED, UNANSWERED, FollowSession)
from semantic_nav.follower import DirectionFollower, FollowerCommand, ModelMissingError
from semantic_nav.instruction_classes import COUNT_CORNERS, COUNT_SIDE
from semantic_nav.laser_layer import model_from_scan

LASER = model_from_scan("utm", -2.35, 0.0043633, 1081)


def test_unsure_reasons_name_each_doubt():
    config = AskConfig()
    assert unsure_reasons([0.99, 0.95], [], [], config) == []
    assert unsure_reasons([0.99, 0.62], [], [], config) == [
        "simple instruction 2 read with confidence 0.62 < 0.9"]
    assert unsure_reasons([1.0], [("lift", "left")], ["um"], config) == [
        "'lift' read as 'left'", "unknown word(s) skipped: um"]
    assert unsure_reasons([1.0], [("lift", "left")], ["um"],
                          AskConfig(misheard=False, unknown=False)) == []
    assert unsure_reasons([0.1], [("lift", "left")], [], AskConfig(enabled=False)) == []


def test_the_robot_says_what_it_understood_with_how_a_count_counts():
    assert describe([1, 3]) == "go straight to the end, then take the first left"
    assert describe([4, 9, 2]) == ("turn around, then go straight to the end and turn right, "
                                   "then take the first right")
    assert describe([5, 8], [COUNT_CORNERS, COUNT_SIDE]) == (
        "turn right at the second corner, then take the third left")
    assert question([6], [COUNT_SIDE]) == ("I understood: take the second left. Shall I go? "
                                           "Please say yes or no.")


@pytest.mark.parametrize("text, reply", [
    ("yes", YES), ("Yes, please.", YES), ("yeah go ahead", YES), ("that's right", YES),
    ("OK", YES), ("no", NO), ("No, that's wrong.", NO), ("that's not right", NO),
    ("don't", NO), ("stop", NO), ("yes no", NO),
    ("turn left", None), ("yes, turn left at the second corner", None), ("", None),
    ("um", None), ("go straight to the end", None)])
def test_a_reply_is_an_answer_only_when_it_names_no_direction(text, reply):
    assert read_answer(text) == reply


class UnsureFollower:
    """Reads every sentence as class 3 with the given confidence and misheard words, and goes at
    0.3 m/s once stepped."""

    control_period = 0.1

    def __init__(self, confidence=0.99, corrections=(), ask=AskConfig()):
        self.confidence, self.corrections, self.config = confidence, list(corrections), \
            type("Config", (), {"ask": ask})()
        self.unknown_words, self.countings, self.stepped = [], [COUNT_CORNERS], 0

    def start(self, sentence):
        self.instructions, self.confidences = [sentence], [self.confidence]
        return [3]

    def step(self, ranges, laser):
        self.stepped += 1
        return FollowerCommand(0.3, 0.0, 0, 3, False)


def test_a_sure_sentence_drives_at_once():
    session = FollowSession(UnsureFollower(), "turn left", now=0.0, max_duration=60.0)
    assert not session.asking and session.question == ""
    assert session.step([1.0] * 1081, LASER, 0.1)[:2] == (0.3, 0.0)


def test_a_yes_drives_with_the_time_limit_counted_from_the_answer():
    follower = UnsureFollower(corrections=[("lift", "left")])
    session = FollowSession(follower, "turn lift", now=0.0, max_duration=20.0)
    assert session.asking and session.unsure == ["'lift' read as 'left'"]
    assert session.question == ("I understood: take the first left. Shall I go? Please say yes "
                                "or no.")
    with pytest.raises(RuntimeError, match="waits on a yes"):
        session.step([1.0] * 1081, LASER, 1.0)
    assert session.wait(10.0).instruction_class == 3 and session.outcome is None
    assert follower.stepped == 0                       # not a single command while asking
    session.answer(YES, now=12.0)
    assert not session.asking
    assert session.step([1.0] * 1081, LASER, 31.0)[:2] == (0.3, 0.0)   # 19 s after the yes
    assert session.outcome is None


def test_a_no_or_silence_never_drives():
    declined = FollowSession(UnsureFollower(confidence=0.6), "turn left", 0.0, 60.0)
    declined.answer(NO, now=3.0)
    assert declined.outcome.status == ABORTED and declined.outcome.completed == 0
    assert declined.outcome.spoken == DECLINED
    assert "was no" in declined.outcome.message
    silent = FollowSession(UnsureFollower(confidence=0.6, ask=AskConfig(answer_timeout=15.0)),
                           "turn left", 0.0, 60.0)
    silent.wait(14.9)
    assert silent.outcome is None
    silent.wait(15.1)
    assert silent.outcome.spoken == UNANSWERED and "no answer" in silent.outcome.message
    with pytest.raises(ValueError, match="an answer is"):
        FollowSession(UnsureFollower(confidence=0.6), "turn left", 0.0, 60.0).answer("maybe",
                                                                                     1.0)


def test_the_default_follower_asks_about_a_misheard_word_only():
    """The committed model: "lift" is read as "left" and asked about; the same direction said
    right drives at once."""
    from semantic_nav.word_vectors import WordVectorsError
    try:
        follower = DirectionFollower.from_files()
    except (ModelMissingError, WordVectorsError) as error:
        pytest.skip(str(error))
    asked = FollowSession(follower, "take the first lift", 0.0, 60.0)
    assert asked.classes == [3] and asked.unsure == ["'lift' read as 'left'"]
    assert asked.question == ("I understood: take the first left. Shall I go? Please say yes "
                              "or no.")
    sure = FollowSession(follower, "go straight to the end, then take the second right", 0.0,
                         60.0)
    assert sure.classes == [1, 5] and not sure.asking
