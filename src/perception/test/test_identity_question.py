"""perception.identity_question: "are you NAME?" to someone the camera cannot tell."""
import pytest

from perception.identity_question import (ASKED, NO, UNANSWERED, YES, IdentityQuestion,
                                          QuestionConfig)


def question(**config):
    return IdentityQuestion(QuestionConfig(**config), "Carol", "dining_room", 10.0)


def test_the_question_names_the_person_looked_for():
    assert question().question() == "Excuse me, are you Carol?"
    called = IdentityQuestion(QuestionConfig(), "Bob", "dining_room", 0.0, call=True)
    assert called.question() == "Bob, are you here?"


def test_a_yes_thanks_them_and_a_no_apologises():
    asked = question()
    reply = asked.hear("Yes.", 12.0)
    assert (reply.say, reply.state) == ("Thank you, Carol.", YES) and not asked.open
    asked = question()
    reply = asked.hear("No, I am Bob.", 12.0)
    assert (reply.say, reply.state) == ("I am sorry, I took you for someone else.", NO)


def test_an_answer_that_is_neither_is_asked_again_once():
    asked = question()
    reply = asked.hear("Maybe", 12.0)
    assert reply.state == ASKED and reply.say.endswith("Excuse me, are you Carol?")
    assert asked.tick(26.9).state == ASKED           # the timeout counts from the re-ask
    reply = asked.hear("Pardon", 13.0)
    assert reply.state == UNANSWERED and not asked.open


def test_silence_leaves_it_unanswered_after_the_timeout():
    asked = question(ask_timeout=15.0)
    assert asked.tick(24.9).state == ASKED
    assert asked.tick(25.0).state == UNANSWERED
    with pytest.raises(RuntimeError, match="unanswered"):
        asked.hear("Yes", 26.0)


def test_an_answer_spoken_in_time_is_waited_for_while_it_is_transcribed():
    """Asked at 10 s: a yes spoken at 21 s whose transcript is still awaited (at 20x real time
    one took 37 s of simulated time) holds the question past the 15 s timeout; once it is no
    longer awaited (PendingTranscripts gave up on it), silence is unanswered. Audio spoken
    before the question or after its timeout holds nothing."""
    asked = question(ask_timeout=15.0)
    assert asked.tick(30.0, [21.0]).state == ASKED
    assert asked.tick(50.0, [21.0]).state == ASKED
    assert asked.hear("Yes.", 51.0).state == YES
    asked = question(ask_timeout=15.0)
    assert asked.tick(39.9, [21.0]).state == ASKED
    assert asked.tick(40.0, []).state == UNANSWERED          # the transcript never came
    for spoken in (9.0, 25.5):
        asked = question(ask_timeout=15.0)
        assert asked.tick(25.0, [spoken]).state == UNANSWERED


def test_a_question_needs_a_name_and_a_place():
    with pytest.raises(ValueError, match="name and a place"):
        IdentityQuestion(QuestionConfig(), "", "dining_room", 0.0)


def test_the_shirt_of_the_one_stranger_seen_at_the_place_is_named():
    """Carol in magenta pyjamas seen in the bedroom: a yes to "are you Carol?" there takes that
    shirt; a second stranger there (Frank's white shirt), nobody, or an old sighting does not."""
    import numpy as np
    import pytest
    from perception.identity_question import RecentStrangers
    magenta = np.array([[200, 30, 200], [186, 26, 188], [190, 28, 192]])
    white = np.array([[236, 236, 230], [222, 222, 216], [226, 226, 220]])
    recent = RecentStrangers(window_s=10.0)
    recent.add(100.0, "bedroom", magenta + 5)
    recent.add(101.0, "bedroom", magenta)
    assert (recent.one_at("bedroom", 102.0) == magenta).all()
    assert recent.one_at("office", 102.0) is None
    assert recent.one_at("bedroom", 112.0) is None                  # older than the window
    recent.add(101.5, "bedroom", white)
    assert recent.one_at("bedroom", 102.0) is None                  # two strangers: no guess
    with pytest.raises(ValueError, match=r"~recall_window must be > 0 \[s\]; got 0"):
        RecentStrangers(window_s=0)


def test_an_utterance_awaits_its_transcript_until_it_comes_or_is_forgotten():
    from perception.identity_question import PendingTranscripts
    pending = PendingTranscripts(wait_s=15.0)      # times on the wall clock
    pending.heard(21.0, now=1000.0)
    pending.heard(30.0, now=1001.0)
    pending.transcribed(21.0)
    assert pending.spoken(now=1015.9) == [30.0]
    pending.heard(95.0, now=1010.0)
    assert pending.spoken(now=1016.0) == [95.0]    # 30 s's transcript never came: forgotten
    assert pending.spoken(now=1025.0) == []
