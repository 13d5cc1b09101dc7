"""Spoken evaluation: sentences spoken in turn by the voices, transcripts followed, misheard
words counted (a stand-in for Whisper; espeak-ng speaks for real)."""
from types import SimpleNamespace

import pytest

from semantic_nav.asking_back import NO, YES, AskConfig
from semantic_nav.follower import UnknownInstructionError
from semantic_nav.instruction_classes import COUNT_CORNERS, COUNT_SIDE
from semnav_learning.evaluation import EpisodeSpec
from semnav_learning.spoken import (Reading, as_meant, misheard_counts, speak_specs,
                                    spoken_report)


class CannedStt:
    """Returns the next canned transcript and keeps how long each audio was."""

    def __init__(self, texts):
        self.texts, self.seconds = list(texts), []

    def transcribe(self, samples):
        self.seconds.append(len(samples) / 16000)
        text = self.texts.pop(0)
        return SimpleNamespace(text=text, held=text.endswith("write."),
                               free_text="Take the second bright." if text.endswith("write.")
                               else "")


def test_sentences_are_spoken_in_turn_and_their_transcripts_followed():
    from perception.speech_synthesis import SynthesisUnavailable
    specs = [EpisodeSpec("f.yaml", (0.0, 0.0, 0.0), (3,), "turn left", False),
             EpisodeSpec("f.yaml", (0.0, 0.0, 0.0), (5,), "take the second right", True)]
    stt = CannedStt(["Turn left.", "Take the second write."])
    try:
        spoken, heard = speak_specs(specs, ["en:175", "en-us:150"], stt)
    except SynthesisUnavailable as error:
        pytest.skip(str(error))
    assert [s.sentence for s in spoken] == ["Turn left.", "Take the second write."]
    assert [s.labels for s in spoken] == [(3,), (5,)]            # the rest of each spec kept
    assert [h.voice for h in heard] == ["en:175", "en-us:150"]
    assert all(0.3 < seconds < 5.0 for seconds in stt.seconds)  # espeak spoke each one
    assert heard[0].misheard == () and heard[1].misheard == (("right", "write"),)
    assert [h.held for h in heard] == [False, True]
    outcomes = [SimpleNamespace(success=True, reason="reached"),
                SimpleNamespace(success=False, reason="stopped outside goal")]
    lines = spoken_report(heard, outcomes)
    assert lines[0] == ("spoken: 2 sentences, word error rate 0.167, 1 heard word for word, 1 "
                        "read held to the STT vocabulary (1 unlike the free reading)")
    assert lines[1:4] == ["  class 1-3 directions driven as a turn around: 0",
                          "  voice en:175: 1/1 reached", "  voice en-us:150: 0/1 reached"]
    assert lines[4:6] == ["failed episodes (said -> heard: why):",
                          "  'take the second right' -> 'Take the second write.': stopped "
                          "outside goal"]
    assert lines[-1] == "  right -> write: 1, 0"
    assert misheard_counts(heard) == {("right", "write"): 1}


class ReadingFollower:
    """Reads canned transcripts as the follower would: {text: (classes, misheard words)};
    anything else is refused."""

    config = SimpleNamespace(ask=AskConfig())

    def __init__(self, readings):
        self.readings = readings

    def start(self, sentence):
        if sentence not in self.readings:
            raise UnknownInstructionError(f"unknown words in {sentence!r}", sentence.split())
        classes, self.corrections = self.readings[sentence]
        self.instructions, self.confidences = [sentence], [0.99] * len(classes)
        self.countings, self.unknown_words = [COUNT_CORNERS] * len(classes), []
        return classes


def test_the_robot_asks_back_and_a_no_or_a_refusal_is_said_again_slower():
    from perception.speech_synthesis import SynthesisUnavailable
    specs = [EpisodeSpec("f.yaml", (0.0, 0.0, 0.0), (3,), "take the first left", False),
             EpisodeSpec("f.yaml", (0.0, 0.0, 0.0), (2,), "take the first right", False),
             EpisodeSpec("f.yaml", (1.0, 2.0, 0.0), (1,), "go to the end", False)]
    follower = ReadingFollower({"Take the first lift.": ([3], [("lift", "left")]),
                                "Take the first right.": ([2], [])})
    stt = CannedStt(["Take the first lift.",                   # asked: meant -> yes
                     "Take the first lift.", "Take the first right.",   # no, then said again
                     "Flibber.", "Flibber."])                  # refused twice: stays
    try:
        spoken, heard = speak_specs(specs, ["en:175", "en-us:150", "en-029:190"], stt,
                                    follower=follower)
    except SynthesisUnavailable as error:
        pytest.skip(str(error))
    first, second, third = heard
    assert first.reading.answer == YES and first.again is None and first.drives
    assert first.reading.question == ("I understood: take the first left. Shall I go? Please "
                                      "say yes or no.")
    assert second.reading.answer == NO and not second.reading.drives
    assert second.again.voice == "en-us:120" and second.again.reading == Reading(True)
    assert second.drives and spoken[1].sentence == "Take the first right."
    assert third.reading.refused and third.again.reading.refused and not third.drives
    assert third.again.voice == "en-029:152"
    lines = spoken_report(heard, [SimpleNamespace(success=True, reason="reached")] * 2 + [
        SimpleNamespace(success=False, reason="stayed: Sorry")])
    assert lines[1] == ("asked back 2 times (1 yes, 1 no), refused 2; said again 2, the robot "
                        "stayed in 1 episodes")
    assert "  'go to the end' -> 'Flibber.', again -> 'Flibber.': stayed: Sorry" in lines


def test_the_robot_understood_as_meant_by_class_and_counting():
    spec = EpisodeSpec("f.yaml", (0.0, 0.0, 0.0), (1, 6), "x", False,
                       (COUNT_CORNERS, COUNT_SIDE))
    assert as_meant(spec, [1, 6], [COUNT_CORNERS, COUNT_SIDE])
    assert not as_meant(spec, [1, 6], [COUNT_CORNERS, COUNT_CORNERS])
    assert not as_meant(spec, [1, 5], [COUNT_CORNERS, COUNT_SIDE])
    assert as_meant(EpisodeSpec("f.yaml", (0, 0, 0), (3,), "x", False), [3], [COUNT_CORNERS])
