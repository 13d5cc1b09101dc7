"""Spoken directions end to end (beyond the seed): an evaluation plan's sentences spoken by
espeak-ng in turn by several voices and speeds, transcribed by Whisper tiny.en (perception's
SpeechToText, the core of the STT node that feeds the semantic_nav node) and followed from the
transcript, as a person's spoken direction reaches the robot. `eval_semnav --spoken VOICE ...`
runs it; the misheard words are listed with how often each was heard so."""
import tempfile
from collections import Counter
from dataclasses import dataclass, replace
from pathlib import Path

DEFAULT_VOICES = ("en:175", "en-us:150", "en-gb-scotland:160", "en-029:190")


@dataclass(frozen=True)
class Heard:
    """One spoken sentence: who said it, what was said and what the robot heard."""

    voice: str       # espeak-ng voice:words-per-minute
    said: str
    heard: str       # Whisper's transcript ("" when it found no speech)
    misheard: tuple  # speech_metrics.misheard_words: ((said word, heard word), ...)
    held: bool = False   # the transcript is the reading held to the STT vocabulary
    free: str = ""       # with an STT vocabulary: the free decoding's text


def speak_specs(specs, voices, stt=None, progress=None):
    """Every spec's sentence spoken (voices in turn) and transcribed -> (specs with the
    transcripts, read as the node reads /voice_message, as their sentences, [Heard]). `stt`: a
    perception SpeechToText (None: one with the STT node's defaults)."""
    from perception.speech_metrics import misheard_words
    from perception.speech_synthesis import synthesise, voice_of
    from perception.stt import SpeechToText, read_wav
    from semantic_nav.instruction_layer import read_transcript
    stt = stt or SpeechToText()
    spoken, heard = [], []
    with tempfile.TemporaryDirectory() as workdir:
        wav = Path(workdir) / "direction.wav"
        for k, spec in enumerate(specs):
            voice = voices[k % len(voices)]
            transcript = stt.transcribe(read_wav(synthesise(spec.sentence, wav, voice_of(voice))))
            text = transcript.text
            heard.append(Heard(voice, spec.sentence, text,
                               tuple(misheard_words(spec.sentence, text)), transcript.held,
                               transcript.free_text))
            spoken.append(replace(spec, sentence=read_transcript(text)))  # as the node reads it
            if progress:
                progress(1)
    return spoken, heard


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
    for voice in dict.fromkeys(h.voice for h in heard):
        mine = [o for h, o in zip(heard, outcomes) if h.voice == voice]
        lines.append(f"  voice {voice}: {sum(o.success for o in mine)}/{len(mine)} reached")
    lines.append("failed episodes (said -> heard: why):")
    lines += [f"  {h.said!r} -> {h.heard!r}: {o.reason}"
              for h, o in zip(heard, outcomes) if not o.success]
    succeeded = Counter(pair for h, o in zip(heard, outcomes) if o.success
                        for pair in h.misheard)
    lines.append("misheard words (said -> heard: times, episodes that still reached the goal):")
    for (said, heard_word), times in misheard_counts(heard).most_common():
        lines.append(f"  {said or '(nothing)'} -> {heard_word or '(nothing)'}: {times}, "
                     f"{succeeded[(said, heard_word)]}")
    return lines
