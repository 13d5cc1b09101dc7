"""Spoken directions end to end (beyond the seed): an evaluation plan's sentences spoken by
espeak-ng in turn by several voices and speeds, transcribed by Whisper tiny.en (perception's
SpeechToText, the core of the STT node that feeds the semantic_nav node) and followed from the
transcript, as a person's spoken direction reaches the robot. `eval_semnav --spoken VOICE ...`
runs it; the misheard words are listed with how often each was heard so.

With a follower (`speak_specs(follower=...)`) the robot takes each transcript as the node does
(`read_as_node`: refused, asked back, or driven at once). A scripted person answers a question
as the one who said the direction would: yes when the robot understood what was meant (the
episode's classes and counting modes), else no. After a no or a refusal they say it once more,
`REPEAT_SPEED` times as fast; a robot that still does not drive stays, and the episode is not
reached."""
import tempfile
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path

from semnav_learning.blind_set import turned_back

DEFAULT_VOICES = ("en:175", "en-us:150", "en-gb-scotland:160", "en-029:190")
REPEAT_SPEED = 0.8       # said again after a no or a refusal, this many times as fast
STAYED = "stayed"        # reason of an episode the robot did not drive after asking back


@dataclass(frozen=True)
class Reading:
    """How the robot took one transcript (follow_session, as the node does)."""

    drives: bool             # followed: sure of it, or asked and answered yes
    question: str = ""       # what it asked back ("": nothing)
    answer: str = ""         # the scripted answer (asking_back.YES / NO)
    refused: str = ""        # why it would not follow ("": it did not refuse)


def as_meant(spec, classes, countings):
    """The robot read the classes of `spec` and, for a counted turn, its counting mode."""
    from semantic_nav.instruction_classes import COUNT_CORNERS, COUNTING_IDS
    meant = list(spec.countings) or [COUNT_CORNERS] * len(spec.labels)
    return list(classes) == list(spec.labels) and all(
        label not in COUNTING_IDS or want == got
        for label, want, got in zip(spec.labels, meant, countings))


def read_as_node(follower, text, spec):
    """The transcript `text` taken as the node takes /voice_message -> Reading; a question
    is answered yes when the robot understood `spec` as meant (as_meant), else no."""
    from semantic_nav.asking_back import NO, YES
    from semantic_nav.follow_session import FollowSession, InstructionRefused
    try:
        session = FollowSession(follower, text, 0.0, 0.0)
    except InstructionRefused as error:
        return Reading(False, refused=error.spoken)
    if not session.asking:
        return Reading(True)
    right = as_meant(spec, session.classes, follower.countings)
    return Reading(right, session.question, YES if right else NO)


def slower(voice):
    """A voice spec said REPEAT_SPEED times as fast ("en:175" -> "en:140")."""
    from perception.speech_synthesis import voice_of
    spoken = voice_of(voice)
    return f"{spoken.name}:{max(1, round(spoken.words_per_min * REPEAT_SPEED))}"


@dataclass(frozen=True)
class Heard:
    """One spoken sentence: who said it, what was said and what the robot heard."""

    voice: str       # espeak-ng voice:words-per-minute
    said: str
    heard: str       # Whisper's transcript ("" when it found no speech)
    misheard: tuple  # speech_metrics.misheard_words: ((said word, heard word), ...)
    held: bool = False   # the transcript is the reading held to the STT vocabulary
    free: str = ""       # with an STT vocabulary: the free decoding's text
    reading: Reading | None = None   # with a follower: how the robot took it
    again: "Heard | None" = None     # said once more after a no or a refusal

    @property
    def drives(self):
        """The robot drove on what it heard last (always, without a follower)."""
        last = self.again or self
        return last.reading is None or last.reading.drives


def speak_specs(specs, voices, stt=None, progress=None, follower=None):
    """Every spec's sentence spoken (voices in turn) and transcribed -> (specs with the
    transcripts, read as the node reads /voice_message, as their sentences, [Heard]). `stt`: a
    perception SpeechToText (None: one with the STT node's defaults). With a `follower` the
    robot asks back as the node does (module comment); Heard.drives says whether it drove."""
    from perception.stt import SpeechToText
    from semantic_nav.instruction_layer import read_transcript
    stt = stt or SpeechToText()
    spoken, heard = [], []
    with tempfile.TemporaryDirectory() as workdir:
        wav = Path(workdir) / "direction.wav"
        for k, spec in enumerate(specs):
            voice = voices[k % len(voices)]
            said = _hear(stt, spec, voice, wav, follower)
            if not said.drives:
                said = replace(said, again=_hear(stt, spec, slower(voice), wav, follower))
            heard.append(said)
            last = said.again or said     # the transcript as the node reads it
            spoken.append(replace(spec, sentence=read_transcript(last.heard)))
            if progress:
                progress(1)
    return spoken, heard


def _hear(stt, spec, voice, wav, follower):
    """spec's sentence said by `voice`, transcribed, and (with a follower) taken -> Heard."""
    from perception.speech_metrics import misheard_words
    from perception.speech_synthesis import synthesise, voice_of
    from perception.stt import read_wav
    from semantic_nav.instruction_layer import read_transcript
    transcript = stt.transcribe(read_wav(synthesise(spec.sentence, wav, voice_of(voice))))
    text = transcript.text
    reading = read_as_node(follower, read_transcript(text), spec) if follower else None
    return Heard(voice, spec.sentence, text, tuple(misheard_words(spec.sentence, text)),
                 transcript.held, transcript.free_text, reading)


def misheard_counts(heard):
    """Counter of (said word, heard word) over every transcript (None: dropped or added)."""
    return Counter(pair for h in heard for pair in h.misheard)


def spoken_report(heard, outcomes):
    """Lines: word error rate, sentences heard exactly, transcripts held to the STT vocabulary,
    per voice success, the failed episodes (said -> heard: why) and the misheard words (said ->
    heard, how often, and how many of those episodes still succeeded)."""
    from perception.speech_metrics import word_error_rate
    wer = word_error_rate([h.said for h in heard], [h.heard for h in heard])
    exact = sum(not h.misheard for h in heard)
    lines = [f"spoken: {len(heard)} sentences, word error rate {wer:.3f}, {exact} heard word "
             f"for word, {sum(h.held for h in heard)} read held to the STT vocabulary "
             f"({sum(h.held and h.heard != h.free for h in heard)} unlike the free reading)"]
    lines += asking_lines(heard)
    back = sum(turned_back([tuple(o.spec.labels)], list(o.predicted))
               for o in outcomes if getattr(o, "predicted", None))
    lines.append(f"  class 1-3 directions driven as a turn around: {back}")
    for voice in dict.fromkeys(h.voice for h in heard):
        mine = [o for h, o in zip(heard, outcomes) if h.voice == voice]
        lines.append(f"  voice {voice}: {sum(o.success for o in mine)}/{len(mine)} reached")
    lines.append("failed episodes (said -> heard: why):")
    lines += [f"  {h.said!r} -> {h.heard!r}"
              + (f", again -> {h.again.heard!r}" if h.again else "") + f": {o.reason}"
              for h, o in zip(heard, outcomes) if not o.success]
    succeeded = Counter(pair for h, o in zip(heard, outcomes) if o.success
                        for pair in h.misheard)
    lines.append("misheard words (said -> heard: times, episodes that still reached the goal):")
    for (said, heard_word), times in misheard_counts(heard).most_common():
        lines.append(f"  {said or '(nothing)'} -> {heard_word or '(nothing)'}: {times}, "
                     f"{succeeded[(said, heard_word)]}")
    return lines


def asking_lines(heard):
    """Lines: how often the robot asked back (answered yes / no), refused, heard a direction
    again, and stayed; [] when it took no transcript (no follower)."""
    from semantic_nav.asking_back import NO, YES
    readings = [r for h in heard for r in (h.reading, h.again and h.again.reading) if r]
    if not readings:
        return []
    asked = [r for r in readings if r.question]
    again = sum(bool(h.again) for h in heard)
    return [f"asked back {len(asked)} times ({sum(r.answer == YES for r in asked)} yes, "
            f"{sum(r.answer == NO for r in asked)} no), refused "
            f"{sum(bool(r.refused) for r in readings)}; said again {again}, the robot stayed in "
            f"{sum(not h.drives for h in heard)} episodes"]
