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


def test_a_question_needs_a_name_and_a_place():
    with pytest.raises(ValueError, match="name and a place"):
        IdentityQuestion(QuestionConfig(), "", "dining_room", 0.0)
