"""Spoken evaluation: sentences spoken in turn by the voices, transcripts followed, misheard
words counted (a stand-in for Whisper; espeak-ng speaks for real)."""
from types import SimpleNamespace

import pytest

from semnav_learning.evaluation import EpisodeSpec
from semnav_learning.spoken import misheard_counts, speak_specs, spoken_report


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
    assert lines[1:3] == ["  voice en:175: 1/1 reached", "  voice en-us:150: 0/1 reached"]
    assert lines[3:5] == ["failed episodes (said -> heard: why):",
                          "  'take the second right' -> 'Take the second write.': stopped "
                          "outside goal"]
    assert lines[-1] == "  right -> write: 1, 0"
    assert misheard_counts(heard) == {("right", "write"): 1}
